// rpu_progen: random shader programs by seed (docs/random-programs.md). Prints them,
// runs them on the functional model and checks that each ends as it must, or measures
// their coverage; the way to reproduce a seed a co-simulation reports.
#include <chrono>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "common/error.hpp"
#include "config/config.hpp"
#include "progen/coverage.hpp"
#include "progen/progen.hpp"
#include "progen/runner.hpp"

namespace rpu::progen {
namespace {

int run(int argc, char** argv) {
  CLI::App app{"rpu_progen: constrained-random shader programs, run on the functional model"};
  std::uint64_t seed = 1, count = 1;
  std::string config_name = "tiny", fault = "halt", scene = "tetra:1";
  std::vector<int> launch;
  bool print = false, coverage = false;
  std::string fault_names = "halt, any";
  for (const FaultClassInfo& f : kFaultClasses) fault_names += fmt::format(", {}", f.name);
  app.add_option("--seed", seed, "the first program's seed")->required();
  app.add_option("--count", count, "programs, seeds seed .. seed + count - 1")->check(CLI::PositiveNumber);
  app.add_option("--config", config_name, "hardware configuration: tiny, default, rpu2005 or a .toml file")
      ->capture_default_str();
  app.add_option("--fault", fault, "what the programs end in: " + fault_names + " (any: each seed its own class)")
      ->capture_default_str();
  app.add_option("--scene", scene, "the scene the programs' rays meet")->capture_default_str();
  app.add_option("--launch", launch, "launch width and height (default: chunk size x 2)")->expected(2);
  app.add_flag("--print", print, "print each program's assembly (and do not run it, unless --coverage)");
  app.add_flag("--coverage", coverage, "run every program and print the coverage of them all");
  CLI11_PARSE(app, argc, argv);

  const spec::HardwareConfig config = config::resolve(config_name);
  const bool any_fault = fault == "any";
  const std::optional<FaultClass> asked = any_fault ? FaultClass::kNone : fault_by_name(fault);
  if (!asked) throw Error(fmt::format("--fault {}: no such class (the classes: {})", fault, fault_names));
  Options options = Options::for_config(config);
  RunnerOptions run_options;
  run_options.scene = scene;
  if (launch.size() == 2) {
    run_options.width = launch[0];
    run_options.height = launch[1];
  }
  std::optional<Runner> runner;
  if (!print || coverage) runner.emplace(config, run_options);

  Coverage total;
  int failures = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t s = seed; s < seed + count; ++s) {
    options.fault = any_fault ? kFaultClasses[s % kFaultClasses.size()].fault : *asked;
    const Program program = generate(s, options);
    if (print) std::fputs(program.assembly().c_str(), stdout);
    if (!runner) continue;
    const Outcome outcome = runner->run(program, coverage ? &total : nullptr);
    total.add_outcome(outcome);
    const std::string problem = unexpected(program, outcome);
    failures += problem.empty() ? 0 : 1;
    if (!problem.empty()) {
      fmt::print("seed {}: UNEXPECTED: {}\n", s, problem);
    } else if (!coverage) {
      fmt::print("seed {}: {} statements, bound {} instructions per thread; {}\n", s, program.statement_count(),
                 program.cost().instructions,
                 outcome.fault ? "faulted as asked: " + *outcome.fault
                               : fmt::format("halted, the busiest thread after {} instructions",
                                             outcome.most_instructions));
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (coverage) {
    std::fputs(total.report(fault != "halt").c_str(), stdout);
    fmt::print("{} programs in {:.2f} s ({:.0f} programs/s), config {}\n", count, seconds,
               static_cast<double>(count) / seconds, config.name);
  }
  return failures ? 1 : 0;
}

}  // namespace
}  // namespace rpu::progen

int main(int argc, char** argv) {
  try {
    return rpu::progen::run(argc, argv);
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "rpu_progen: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rpu_progen: internal error: %s\n", e.what());
    return 2;
  }
}
