// Random programs by the thousand on the functional model, per named configuration:
// each halts within its instruction bound (termination by construction) or ends in the
// fault it was made for, at the first faulting pixel its condition names; together
// they cover every instruction of spec/isa.toml, every modifier, swizzle kind, write
// mask and event class, and every fault class. RPU_PROGEN_SEEDS sets the number of
// halting programs per configuration (default 1000, or 250 under AddressSanitizer, which
// runs them 10 times slower; fault programs: a twentieth of it per class, at least 12).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "common/hardware_config.hpp"
#include "progen/coverage.hpp"
#include "progen/progen.hpp"
#include "progen/runner.hpp"

namespace rpu::progen {
namespace {

std::uint64_t seeds() {
  if (const char* text = std::getenv("RPU_PROGEN_SEEDS")) return std::strtoull(text, nullptr, 10);
#ifdef __SANITIZE_ADDRESS__
  return 250;
#else
  return 1000;
#endif
}

// The command that reproduces a failing seed.
std::string reproduce(std::uint64_t seed, const std::string& config, FaultClass fault) {
  return fmt::format("build/release/rpu_progen --seed {} --config {} --fault {} --print", seed, config,
                     fault_name(fault));
}

// Runs one program into `coverage`; false, with the failure and how to reproduce it,
// if it did not end as it must.
bool ends_as_it_must(const Runner& runner, const Program& program, Coverage& coverage, const std::string& config) {
  const Outcome outcome = runner.run(program, &coverage);
  coverage.add_outcome(outcome);
  const std::string problem = unexpected(program, outcome);
  if (problem.empty()) return true;
  ADD_FAILURE() << "seed " << program.seed << ": " << problem << "\n  reproduce: "
                << reproduce(program.seed, config, program.fault);
  return false;
}

class ProgenSweep : public testing::TestWithParam<std::string> {};

TEST_P(ProgenSweep, ProgramsHaltWithinTheirBoundAndCoverTheIsa) {
  const spec::HardwareConfig& config = hardware_config(GetParam());
  const Runner runner(config);
  const Options options = Options::for_config(config);
  Coverage coverage;
  int failures = 0;
  for (std::uint64_t seed = 1; seed <= seeds() && failures < 10; ++seed) {
    failures += ends_as_it_must(runner, generate(seed, options), coverage, GetParam()) ? 0 : 1;
  }
  for (const std::string& item : coverage.missing(false)) ADD_FAILURE() << "never covered: " << item;
  if (HasFailure()) std::fputs(coverage.report(false).c_str(), stderr);
}

TEST_P(ProgenSweep, FaultProgramsEndInTheirFaultAtTheFirstFaultingPixel) {
  const spec::HardwareConfig& config = hardware_config(GetParam());
  const Runner runner(config);
  Options options = Options::for_config(config);
  Coverage coverage;
  const std::uint64_t per_class = std::max<std::uint64_t>(12, seeds() / 20);
  int failures = 0, later_pixel = 0;
  for (const FaultClassInfo& f : kFaultClasses) {
    options.fault = f.fault;
    for (std::uint64_t seed = 1; seed <= per_class && failures < 10; ++seed) {
      const Program program = generate(seed, options);
      failures += ends_as_it_must(runner, program, coverage, GetParam()) ? 0 : 1;
      later_pixel += program.fault_pixel() == 1u ? 1 : 0;
    }
  }
  // Most faults run where a condition on the pixel holds, so pixel 0 halts and pixel 1
  // is the one reported while later pixels fault too.
  EXPECT_GT(later_pixel, static_cast<int>(per_class * kFaultClasses.size() / 2));
  // The other items are the halting programs' test's.
  for (const std::string& item : coverage.missing(true)) {
    if (item.starts_with("fault:")) ADD_FAILURE() << "never covered: " << item;
  }
  if (HasFailure()) std::fputs(coverage.report(true).c_str(), stderr);
}

INSTANTIATE_TEST_SUITE_P(Configs, ProgenSweep, testing::Values("tiny", "default", "rpu2005"),
                         [](const testing::TestParamInfo<std::string>& i) { return i.param; });

}  // namespace
}  // namespace rpu::progen
