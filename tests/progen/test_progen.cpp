// The random-program generator (docs/random-programs.md): its random numbers, its
// determinism, the fault classes it reads from the functional model's messages, and
// the shrinker.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "progen/coverage.hpp"
#include "progen/progen.hpp"
#include "progen/random.hpp"
#include "progen/runner.hpp"

namespace rpu::progen {
namespace {

namespace fs = std::filesystem;

// The first outputs of SplitMix64 from state 0, from its reference implementation
// (Vigna's splitmix64.c): the same seed must give the same program on every host.
TEST(Progen, RandomIsSplitMix64) {
  Random r(0);
  EXPECT_EQ(r.next(), 0xe220a8397b1dcdafull);
  EXPECT_EQ(r.next(), 0x6e789e6aa1b965f4ull);
  EXPECT_EQ(r.next(), 0x06c45d188009454full);
}

TEST(Progen, SameSeedGivesTheSameProgramText) {
  for (const char* name : {"tiny", "rpu2005"}) {
    Options options = Options::for_config(hardware_config(name));
    for (const FaultClass fault : {FaultClass::kNone, FaultClass::kStackOverflow}) {
      options.fault = fault;
      std::set<std::string> texts;
      for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        const std::string text = generate(seed, options).assembly();
        EXPECT_EQ(text, generate(seed, options).assembly()) << name << " seed " << seed;
        texts.insert(text);
      }
      EXPECT_EQ(texts.size(), 20u) << "twenty seeds should give twenty programs";
    }
  }
}

// The assembly names what each statement is for, so that a shrunk program reads.
TEST(Progen, AssemblyCommentsNameTheStatements) {
  const Options options = Options::for_config(hardware_config("tiny"));
  std::string all;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) all += generate(seed, options).assembly();
  for (const char* comment : {"; if ", "; loop of at most", "; prologue", "push and as many pops", "of a camera ray",
                              "; load from", "; function, level", "; hit shader, id", "; calli shader"}) {
    EXPECT_NE(all.find(comment), std::string::npos) << comment;
  }
}

TEST(Progen, OptionsTheGeneratorCannotMeetAreErrors) {
  const Options tiny = Options::for_config(hardware_config("tiny"));
  Options options = tiny;
  options.machine.registers = 64;  // no register past the count
  options.fault = FaultClass::kIllegalRegister;
  EXPECT_THROW(generate(1, options), Error);
  options = tiny;
  options.machine.registers = 4;  // the plan's three registers leave too few free
  EXPECT_THROW(generate(1, options), Error);
  options = tiny;
  options.max_statements = 0;
  EXPECT_THROW(generate(1, options), Error);
  options = tiny;
  options.fault = FaultClass::kWatchdog;
  options.watchdog = 10;
  EXPECT_THROW(generate(1, options), Error);
}

TEST(Progen, FaultNamesReadBack) {
  for (const FaultClassInfo& f : kFaultClasses) EXPECT_EQ(fault_by_name(fault_name(f.fault)), f.fault);
  EXPECT_EQ(fault_by_name("halt"), FaultClass::kNone);
  EXPECT_EQ(fault_by_name("no-such-fault"), std::nullopt);
}

// The fault messages tests/isa/programs/fault_*.exp expect from the functional model,
// written by hand there, each read as the class its program shows. Every such program
// must be listed here, so that a new fault there is noticed, and every class must
// have one.
TEST(Progen, FaultClassesReadTheModelsMessages) {
  const std::map<std::string, FaultClass> expected{
      {"fault_call_depth", FaultClass::kCallDepthOverflow},
      {"fault_illegal_opcode", FaultClass::kIllegalOpcode},
      {"fault_illegal_register", FaultClass::kIllegalRegister},
      {"fault_illegal_register_source", FaultClass::kIllegalRegister},
      {"fault_illegal_register_store", FaultClass::kIllegalRegister},
      {"fault_illegal_special", FaultClass::kIllegalSpecial},
      {"fault_illegal_st1_mask", FaultClass::kIllegalSt1Mask},
      {"fault_illegal_unused_bits", FaultClass::kIllegalUnusedField},
      {"fault_mfra_empty", FaultClass::kReturnStackEmpty},
      {"fault_misaligned", FaultClass::kMisaligned},
      {"fault_misaligned_store", FaultClass::kMisaligned},
      {"fault_mtra_overflow", FaultClass::kCallDepthOverflow},
      {"fault_out_of_range_data_end", FaultClass::kOutOfRangeUnmapped},
      {"fault_out_of_range_other_pixel", FaultClass::kOutOfRangeOtherPixel},
      {"fault_out_of_range_other_pixel_load", FaultClass::kOutOfRangeOtherPixel},
      {"fault_out_of_range_segment_end", FaultClass::kOutOfRangeSegmentEnd},
      {"fault_out_of_range_stack", FaultClass::kOutOfRangeStack},
      {"fault_out_of_range_store_data", FaultClass::kOutOfRangeReadOnly},
      {"fault_out_of_range_store_image", FaultClass::kOutOfRangeReadOnly},
      {"fault_out_of_range_unmapped", FaultClass::kOutOfRangeUnmapped},
      {"fault_pc", FaultClass::kPc},
      {"fault_pc_branch", FaultClass::kPc},
      {"fault_ret_empty", FaultClass::kReturnStackEmpty},
      {"fault_shader_id", FaultClass::kShaderId},
      {"fault_stack_overflow", FaultClass::kStackOverflow},
      {"fault_stack_underflow", FaultClass::kStackUnderflow},
      {"fault_spin", FaultClass::kSpin},
      {"fault_watchdog", FaultClass::kWatchdog},
  };
  std::set<FaultClass> seen;
  int files = 0;
  for (const auto& entry : fs::directory_iterator(RPU_ISA_PROGRAM_DIR)) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() != ".exp" || !stem.starts_with("fault_")) continue;
    ++files;
    const auto want = expected.find(stem);
    ASSERT_NE(want, expected.end()) << stem << ".exp: a fault program this test does not know; add its class";
    std::ifstream in(entry.path());
    std::string line, message;
    while (std::getline(in, line)) {
      if (line.starts_with("fault \"")) message = line.substr(7, line.rfind('"') - 7);
    }
    ASSERT_FALSE(message.empty()) << stem << ".exp has no fault line";
    const std::optional<FaultClass> got = classify_fault_message(message);
    EXPECT_EQ(got ? fault_name(*got) : "no class", fault_name(want->second)) << stem << ": " << message;
    seen.insert(want->second);
  }
  EXPECT_EQ(files, static_cast<int>(expected.size()));
  for (const FaultClassInfo& f : kFaultClasses) EXPECT_TRUE(seen.count(f.fault)) << f.name << " has no program";
}

// Sees whether a dp4 issues while some live lanes of its chunk are masked off.
class DivergentDp4 final : public StepObserver {
 public:
  bool found = false;
  void before_step(const functional::ShaderCore::Chunk& chunk) override {
    live_ = 0;
    for (std::size_t l = 0; l < chunk.threads().size(); ++l) live_ |= chunk.threads()[l].done ? 0u : 1u << l;
  }
  void after_step(const functional::StepRecord& r, const functional::ShaderCore::Chunk&) override {
    found |= r.insn && r.insn->opcode() == isa::Opcode::kDp4 && r.lanes != live_;
  }

 private:
  std::uint32_t live_ = 0;
};

TEST(Progen, ShrinkKeepsADivergentDp4InAMuchSmallerLegalProgram) {
  const spec::HardwareConfig& config = hardware_config("tiny");
  const Runner runner(config);
  const auto divergent_dp4 = [&](const Program& p) {
    DivergentDp4 seen;
    runner.run(p, &seen);
    return seen.found;
  };
  const Options options = Options::for_config(config);
  std::uint64_t seed = 1;
  while (!divergent_dp4(generate(seed, options))) ++seed;
  const Program original = generate(seed, options);
  int calls = 0;
  const Program shrunk = shrink(original, [&](const Program& p) {
    ++calls;
    return divergent_dp4(p);
  });
  SCOPED_TRACE(fmt::format("seed {}: {} statements shrunk to {} in {} runs:\n{}", seed, original.statement_count(),
                           shrunk.statement_count(), calls, shrunk.assembly()));
  EXPECT_TRUE(divergent_dp4(shrunk));
  EXPECT_EQ(unexpected(shrunk, runner.run(shrunk)), "");
  // What it needs: a condition, and a dp4 where it holds (or lanes that halt first).
  EXPECT_LE(shrunk.statement_count(), 3u);
  EXPECT_LT(shrunk.statement_count() * 20, original.statement_count());
  EXPECT_EQ(shrink(original, divergent_dp4).assembly(), shrunk.assembly()) << "the shrinker is not deterministic";
}

TEST(Progen, ShrinkKeepsAFaultAndItsFirstFaultingPixel) {
  const spec::HardwareConfig& config = hardware_config("default");
  const Runner runner(config);
  Options options = Options::for_config(config);
  for (const FaultClass fault :
       {FaultClass::kStackOverflow, FaultClass::kShaderId, FaultClass::kOutOfRangeOtherPixel}) {
    options.fault = fault;
    const Program original = generate(3, options);
    const Program shrunk = shrink(original, [&](const Program& p) { return unexpected(p, runner.run(p)).empty(); });
    SCOPED_TRACE(shrunk.assembly());
    EXPECT_EQ(unexpected(shrunk, runner.run(shrunk)), "");
    // The fault's code, and the condition it stands in where pixel 0 must not run it.
    EXPECT_LE(shrunk.statement_count(), 2u) << fault_name(fault);
  }
}


// The shrinker edits only in ways the generator's rules allow: every candidate it makes,
// not only the one it returns, halts within its bound or ends in its program's fault.
TEST(Progen, EveryCandidateOfTheShrinkerIsLegal) {
  int shrinks = 0, all_candidates = 0;
  for (const char* name : {"tiny", "rpu2005"}) {
    const spec::HardwareConfig& config = hardware_config(name);
    const Runner runner(config);
    Options options = Options::for_config(config);
    for (const FaultClass fault : {FaultClass::kNone, FaultClass::kCallDepthOverflow, FaultClass::kShaderId,
                                   FaultClass::kOutOfRangeOtherPixel, FaultClass::kWatchdog}) {
      options.fault = fault;
      // 16 seeds: a seed's program depends on the compiler (the generator passes several
      // draws as one call's arguments, in an order C++ leaves open), and GCC's and clang's
      // programs each give enough shrinks over 16.
      for (std::uint64_t seed = 1; seed <= 16; ++seed) {
        int candidates = 0;
        // A property that needs calls and rays: a nested call, and a ray that hits.
        const auto nested_call_and_hit = [&](const Program& p) {
          ++candidates;
          Coverage seen;
          const Outcome outcome = runner.run(p, &seen);
          const std::string problem = unexpected(p, outcome);
          // A fault program that lost its fault code halts: legal too, within its bound.
          const bool legal =
              problem.empty() || (!outcome.fault && outcome.most_instructions <= p.cost().instructions);
          EXPECT_TRUE(legal) << name << " seed " << seed << " candidate " << candidates << ": " << problem << "\n"
                             << p.assembly();
          return seen.count("control", "call or calli at return-stack depth >= 2") > 0 &&
                 seen.count("ray", "trace hit") + seen.count("ray", "tracea hit") > 0;
        };
        const Program original = generate(seed, options);
        if (!nested_call_and_hit(original)) continue;
        shrink(original, nested_call_and_hit);
        if (HasFailure()) return;
        ++shrinks;
        all_candidates += candidates;
      }
    }
  }
  EXPECT_GE(shrinks, 20);
  EXPECT_GE(all_candidates, 2000);
}

}  // namespace
}  // namespace rpu::progen
