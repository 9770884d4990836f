// OTBN-style instruction tests: each tests/isa/programs/NAME.s runs as one thread on
// the functional shader core, and NAME.exp states, by hand, what must hold when it
// stops: register lanes, the thread's framebuffer pixel, or the fault message.
//
// .exp lines (# starts a comment):
//   config NAME          hardware configuration (default tiny)
//   format NAME          number format (default: the configuration's)
//   scene ARG            scene for trace (default tetra:1), as `rpu render` takes it
//   launch W H           launch size (default 1 1); the thread runs pixel (W*H - 1)
//   rN = a b c d         all four lanes; rN.xz = a b   the named lanes, in order
//   fb = a b c d         the thread's framebuffer pixel
//   fault "text"         the run faults and its message contains text
// A lane value is an integer (decimal or 0x hex: raw bits) or a number with a '.'
// or exponent, inf, -inf, nan (the fp32 bits of that float).
// Programs in fp32 run twice, on the fast32 and on the soft float path; both must match.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "functional/scene_image.hpp"
#include "functional/shader_core.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;
using Vec = std::array<std::uint32_t, 4>;

struct LaneCheck {
  int reg = -1;  // -1: the framebuffer pixel
  std::vector<int> lanes;
  std::vector<std::uint32_t> values;
  int line = 0;
};

struct Expectation {
  std::string config = "tiny";
  std::string format;
  std::string scene = "tetra:1";
  int width = 1, height = 1;
  std::vector<LaneCheck> checks;
  std::optional<std::string> fault;
};

std::uint32_t parse_value(const std::string& token, const std::string& where) {
  const bool is_float = token.find_first_of(".eE") != std::string::npos && token.rfind("0x", 0) != 0;
  if (token == "inf" || token == "-inf" || token == "nan" || is_float) {
    if (token == "nan") return 0x7fc00000u;
    return std::bit_cast<std::uint32_t>(std::stof(token));
  }
  try {
    const long long v = std::stoll(token, nullptr, 0);
    return static_cast<std::uint32_t>(v);
  } catch (const std::exception&) {
    ADD_FAILURE() << where << ": bad value '" << token << "'";
    return 0;
  }
}

Expectation parse_expectation(const fs::path& file) {
  Expectation e;
  std::ifstream in(file);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) continue;
    const std::string where = fmt::format("{}:{}", file.string(), n);
    if (key == "config") {
      words >> e.config;
    } else if (key == "format") {
      words >> e.format;
    } else if (key == "scene") {
      words >> e.scene;
    } else if (key == "launch") {
      words >> e.width >> e.height;
    } else if (key == "fault") {
      const auto q0 = line.find('"'), q1 = line.rfind('"');
      EXPECT_NE(q0, q1) << where << ": fault \"text\"";
      e.fault = line.substr(q0 + 1, q1 - q0 - 1);
    } else {
      LaneCheck c;
      c.line = n;
      std::string name = key, eq;
      std::string lanes = "xyzw";
      if (const auto dot = key.find('.'); dot != std::string::npos) {
        name = key.substr(0, dot);
        lanes = key.substr(dot + 1);
      }
      if (name == "fb") {
        c.reg = -1;
      } else if (name.size() > 1 && name[0] == 'r') {
        c.reg = std::stoi(name.substr(1));
      } else {
        ADD_FAILURE() << where << ": unknown key '" << key << "'";
        continue;
      }
      for (const char l : lanes) c.lanes.push_back(static_cast<int>(std::string_view("xyzw").find(l)));
      words >> eq;
      EXPECT_EQ(eq, "=") << where;
      for (std::string v; words >> v;) c.values.push_back(parse_value(v, where));
      EXPECT_EQ(c.values.size(), c.lanes.size()) << where << ": one value per lane";
      e.checks.push_back(c);
    }
  }
  return e;
}

std::vector<std::string> program_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(RPU_ISA_PROGRAM_DIR)) {
    if (entry.path().extension() == ".s") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

class IsaProgram : public testing::TestWithParam<std::string> {};

TEST_P(IsaProgram, EndStateMatchesExp) {
  const fs::path dir = RPU_ISA_PROGRAM_DIR;
  const fs::path source = dir / (GetParam() + ".s");
  const fs::path exp_file = dir / (GetParam() + ".exp");
  ASSERT_TRUE(fs::exists(exp_file)) << exp_file << " is missing";
  const Expectation e = parse_expectation(exp_file);

  const spec::HardwareConfig* config = &hardware_config(e.config);
  const fp::Format format = fp::format_by_name(e.format.empty() ? std::string(config->format) : e.format);
  const Scene scene = resolve_scene(e.scene);
  KdBuildConfig build = kd_build_config_for(std::string(config->name));
  build.format = format;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const isa::Firmware firmware = isa::assemble(source);

  device::Launch launch{e.width, e.height, 1, 0, 1};
  const functional::Tracer tracer(si.image.bytes, si.layout, format, config->stack_depth);
  const functional::ShaderCoreConfig cc = functional::ShaderCoreConfig::of(*config, 100'000);
  const std::uint32_t pixel = static_cast<std::uint32_t>(e.width * e.height - 1);
  const functional::ShaderCore::Lane lane{0, 0, 0, 0, pixel};
  // fp32 programs run on both float paths (host floats under FTZ/DAZ, and the soft
  // path), which must agree bit for bit; other formats have only the soft path.
  for (const bool fast : {true, false}) {
    if (fast && format != fp::kFp32) continue;
    SCOPED_TRACE(fast ? "fp32 fast path (fp::fast32)" : "soft path (fp::soft)");
    functional::DeviceMemory memory(si.image.bytes,
                                    device::make_launch_block(si.image.bytes, si.layout, launch, {}), firmware.data,
                                    static_cast<std::uint32_t>(e.width * e.height));
    functional::ShaderCore core(firmware, memory, tracer, format, cc, fast);
    functional::ShaderStats stats;
    std::vector<std::vector<Vec>> regs;
    if (e.fault) {
      try {
        core.run_chunk({&lane, 1}, stats, &regs);
        ADD_FAILURE() << source.string() << ": expected a fault containing \"" << *e.fault
                      << "\", but the program halted";
      } catch (const functional::ShaderFault& f) {
        EXPECT_NE(std::string(f.what()).find(*e.fault), std::string::npos)
            << source.string() << ": fault message\n  " << f.what() << "\ndoes not contain\n  " << *e.fault;
      }
      continue;
    }
    core.run_chunk({&lane, 1}, stats, &regs);
    ASSERT_EQ(regs.size(), 1u);
    for (const LaneCheck& c : e.checks) {
      Vec have{};
      if (c.reg < 0) {
        const auto fb = memory.framebuffer().subspan(pixel * 16, 16);
        std::memcpy(have.data(), fb.data(), 16);
      } else {
        ASSERT_LT(c.reg, static_cast<int>(regs[0].size())) << exp_file.string() << ":" << c.line;
        have = regs[0][static_cast<std::size_t>(c.reg)];
      }
      for (std::size_t i = 0; i < c.lanes.size() && i < c.values.size(); ++i) {
        const std::uint32_t got = have[static_cast<std::size_t>(c.lanes[i])];
        EXPECT_EQ(got, c.values[i]) << fmt::format(
            "{}:{}: {}.{} is {:#010x} ({}), expected {:#010x} ({})", exp_file.string(), c.line,
            c.reg < 0 ? std::string("fb") : fmt::format("r{}", c.reg), "xyzw"[c.lanes[i]], got,
            std::bit_cast<float>(got), c.values[i], std::bit_cast<float>(c.values[i]));
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Programs, IsaProgram, testing::ValuesIn(program_names()),
                         [](const testing::TestParamInfo<std::string>& i) { return i.param; });

// Every instruction of spec/isa.toml has a program named after it.
TEST(IsaPrograms, EveryInstructionHasAProgram) {
  const std::vector<std::string> names = program_names();
  for (const spec::isa::InsnSpec& insn : spec::isa::kInsns) {
    EXPECT_TRUE(std::find(names.begin(), names.end(), std::string(insn.mnemonic)) != names.end())
        << "tests/isa/programs/" << insn.mnemonic << ".s is missing";
  }
}

}  // namespace
}  // namespace rpu
