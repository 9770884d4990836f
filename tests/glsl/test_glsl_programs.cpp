// GLSL programs with stated outcomes, like tests/isa's: each tests/glsl/programs/NAME/
// holds the shaders of one firmware (raygen.rgen, and any .rchit and .rmiss) and an
// `expect` file. The firmware is compiled at -O0 and at -O2 and run on the functional
// device; both must meet every expectation.
//
// expect lines (# starts a comment):
//   scene ARG              scene, as `rpu render` takes it (default tetra:1)
//   launch W H             image size (default 1 1)
//   max-depth N            launch max depth (default 2)
//   config NAME            hardware configuration (default default)
//   registers N            compile for N registers (default 16)
//   fb X Y = r g b         the pixel's colour: numbers (a '.', exponent, inf, nan) or 0x raw bits
//   fb X Y ~ r g b tol     the same within tol
//   define NAME[=VALUE]    compile with -D NAME[=VALUE]
//   include DIR            compile with -I DIR (relative to the program's directory)
//   spec ID=VALUE          compile with --spec-constant ID=VALUE
//   warning "text"         compiling warns with a message containing text (no warning
//                          is allowed without one)
//   error "text"           compiling fails with a message containing text (each of
//                          several error lines)
//   fault "text"           the run faults with a message containing text
// A program without whitted.rchit gets an empty one (the test scenes' materials name it).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cc/compiler.hpp"
#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

struct PixelCheck {
  int x = 0, y = 0;
  std::array<float, 3> rgb{};
  std::optional<float> tolerance;
  int line = 0;
};

struct Expectation {
  std::string scene = "tetra:1";
  std::string config = "default";
  int width = 1, height = 1, max_depth = 2, registers = 16;
  std::vector<PixelCheck> pixels;
  std::vector<std::string> defines, includes, specs;
  std::vector<std::string> errors;
  std::optional<std::string> warning, fault;
};

float parse_number(const std::string& token) {
  if (token.rfind("0x", 0) == 0) return std::bit_cast<float>(static_cast<std::uint32_t>(std::stoul(token, nullptr, 16)));
  if (token == "nan") return std::numeric_limits<float>::quiet_NaN();
  return std::stof(token);
}

std::string quoted(const std::string& line, const std::string& where) {
  const auto a = line.find('"'), b = line.rfind('"');
  EXPECT_NE(a, b) << where << ": expected \"text\"";
  return a == b ? std::string() : line.substr(a + 1, b - a - 1);
}

Expectation parse_expectation(const fs::path& file) {
  Expectation e;
  std::ifstream in(file);
  EXPECT_TRUE(in) << file << " is missing";
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) continue;
    const std::string where = fmt::format("{}:{}", file.string(), n);
    if (key == "scene") {
      words >> e.scene;
    } else if (key == "config") {
      words >> e.config;
    } else if (key == "launch") {
      words >> e.width >> e.height;
    } else if (key == "max-depth") {
      words >> e.max_depth;
    } else if (key == "registers") {
      words >> e.registers;
    } else if (key == "define" || key == "include" || key == "spec") {
      std::string value;
      words >> value;
      (key == "define" ? e.defines : key == "include" ? e.includes : e.specs).push_back(value);
    } else if (key == "warning") {
      e.warning = quoted(line, where);
    } else if (key == "error") {
      e.errors.push_back(quoted(line, where));
    } else if (key == "fault") {
      e.fault = quoted(line, where);
    } else if (key == "fb") {
      PixelCheck c;
      c.line = n;
      std::string op;
      words >> c.x >> c.y >> op;
      for (float& v : c.rgb) {
        std::string t;
        words >> t;
        v = parse_number(t);
      }
      if (op == "~") {
        std::string t;
        words >> t;
        c.tolerance = parse_number(t);
      } else {
        EXPECT_EQ(op, "=") << where;
      }
      e.pixels.push_back(c);
    } else {
      ADD_FAILURE() << where << ": unknown key '" << key << "'";
    }
  }
  return e;
}

std::vector<std::string> program_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(RPU_GLSL_PROGRAM_DIR)) {
    if (entry.is_directory()) names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

class GlslProgram : public testing::TestWithParam<std::string> {};

TEST_P(GlslProgram, MeetsItsExpectations) {
  const fs::path dir = fs::path(RPU_GLSL_PROGRAM_DIR) / GetParam();
  const fs::path expect_file = dir / "expect";
  const Expectation e = parse_expectation(expect_file);
  // raygen first, then hit shaders, then miss shaders in name order (miss index order).
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".rgen" || ext == ".rchit" || ext == ".rmiss" || ext == ".rahit") files.push_back(entry.path());
  }
  const auto rank = [](const fs::path& p) {
    const std::string ext = p.extension().string();
    return ext == ".rgen" ? 0 : ext == ".rchit" ? 1 : 2;
  };
  std::sort(files.begin(), files.end(), [&](const fs::path& a, const fs::path& b) {
    return std::make_pair(rank(a), a.filename()) < std::make_pair(rank(b), b.filename());
  });

  // The test scenes' materials use the shader 'whitted': a program that does not trace
  // gets an empty one.
  std::vector<cc::ShaderSource> sources;
  bool has_whitted = false;
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    sources.push_back({f, text.str()});
    has_whitted |= f.filename() == "whitted.rchit";
  }
  if (!has_whitted) {
    sources.push_back({dir / "whitted.rchit", "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n"});
  }

  const spec::HardwareConfig& config = hardware_config(e.config);
  const fp::Format format = fp::format_by_name(std::string(config.format));
  const Scene scene = resolve_scene(e.scene);
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  build.format = format;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);

  for (const int level : {0, 2}) {
    SCOPED_TRACE(fmt::format("-O{}", level));
    cc::CompileOptions options;
    options.opt_level = level;
    options.registers = e.registers;
    options.defines = e.defines;
    for (const std::string& d : e.includes) options.include_dirs.push_back(dir / d);
    isa::Firmware firmware;
    try {
      for (const std::string& s : e.specs) options.spec_constants.insert(cc::parse_spec_constant(s));
      cc::Compiled compiled = cc::compile(sources, options);
      firmware = std::move(compiled.firmware);
      const std::string warnings = fmt::format("{}", fmt::join(compiled.warnings, "\n"));
      if (e.warning) {
        EXPECT_NE(warnings.find(*e.warning), std::string::npos)
            << dir.string() << ": the warnings\n  " << warnings << "\ndo not contain\n  " << *e.warning;
      } else {
        EXPECT_EQ(warnings, "") << dir.string() << ": warnings no `warning` line expects";
      }
      if (!e.errors.empty()) {
        ADD_FAILURE() << dir.string() << ": expected a compile error containing \"" << e.errors[0]
                      << "\", but it compiled";
        continue;
      }
    } catch (const Error& err) {
      if (e.errors.empty()) throw;
      for (const std::string& text : e.errors) {
        EXPECT_NE(std::string(err.what()).find(text), std::string::npos)
            << dir.string() << ": the message\n  " << err.what() << "\ndoes not contain\n  " << text;
      }
      continue;
    }
    RenderSettings settings;
    settings.width = e.width;
    settings.height = e.height;
    settings.spp = 1;
    settings.max_depth = e.max_depth;
    settings.threads = 1;
    const auto dev = device::make_functional_device(config, format);
    Image image;
    try {
      image = device::render_frame(*dev, scene, si.image, firmware, settings);
      if (e.fault) {
        ADD_FAILURE() << dir.string() << ": expected a fault containing \"" << *e.fault << "\", but it ran";
        continue;
      }
    } catch (const std::exception& err) {
      if (!e.fault) throw;
      EXPECT_NE(std::string(err.what()).find(*e.fault), std::string::npos)
          << dir.string() << ": the fault\n  " << err.what() << "\ndoes not contain\n  " << *e.fault;
      continue;
    }
    for (const PixelCheck& c : e.pixels) {
      const glm::vec3 have = image.at(c.x, c.y);
      for (int k = 0; k < 3; ++k) {
        const float got = have[k], want = c.rgb[static_cast<std::size_t>(k)];
        const bool ok = c.tolerance ? std::abs(got - want) <= *c.tolerance
                                    : std::bit_cast<std::uint32_t>(got) == std::bit_cast<std::uint32_t>(want);
        EXPECT_TRUE(ok) << fmt::format("{}:{}: pixel ({}, {}) {} is {} ({:#010x}), expected {}{}", expect_file.string(),
                                       c.line, c.x, c.y, "rgb"[k], got, std::bit_cast<std::uint32_t>(got), want,
                                       c.tolerance ? fmt::format(" within {}", *c.tolerance) : "");
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Programs, GlslProgram, testing::ValuesIn(program_names()),
                         [](const testing::TestParamInfo<std::string>& i) { return i.param; });


// The library's inverse trigonometry and tan against libm in double, on fp32 (default),
// over the 512x512 grids of tests/glsl/accuracy: the bounds docs/shaders.md states.
Image render_accuracy_grid(const std::string& raygen) {
  const fs::path file = fs::path(RPU_GLSL_ACCURACY_DIR) / raygen;
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::vector<cc::ShaderSource> sources{
      {file, text.str()},
      {file.parent_path() / "whitted.rchit", "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n"}};
  const isa::Firmware firmware = cc::compile(sources, cc::CompileOptions{}).firmware;
  const spec::HardwareConfig& config = hardware_config("default");
  const Scene scene = resolve_scene("tetra:1");
  const functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWoop);
  RenderSettings settings;
  settings.width = 512;
  settings.height = 512;
  settings.spp = 1;
  settings.max_depth = 1;
  const auto dev = device::make_functional_device(config, fp::kFp32);
  return device::render_frame(*dev, scene, si.image, firmware, settings);
}

TEST(GlslMath, InverseTrigonometryAndTanAreWithinTheirStatedError) {
  const Image inverse = render_accuracy_grid("inverse_trig.rgen");
  const Image tangent = render_accuracy_grid("tangent.rgen");
  double atan1 = 0, asin1 = 0, acos1 = 0, atan2_grid = 0, atan2_steep = 0, tan_relative = 0;
  for (int y = 0; y < 512; ++y) {
    for (int x = 0; x < 512; ++x) {
      const float d = static_cast<float>(512 * y + x - 131072);
      const double t = d / 4096.0f, s = d / 131072.0f, a = d * 1.1980533599853516e-05f;
      const double u = static_cast<float>(x - 256) / 64.0f, v = static_cast<float>(y - 256) / 64.0f;
      const glm::vec3 i = inverse.at(x, y), g = tangent.at(x, y);
      atan1 = std::max(atan1, std::abs(i.x - std::atan(t)));
      asin1 = std::max(asin1, std::abs(i.y - std::asin(s)));
      acos1 = std::max(acos1, std::abs(i.z - std::acos(s)));
      if (a != 0) tan_relative = std::max(tan_relative, std::abs(g.x - std::tan(a)) / std::abs(std::tan(a)));
      if (u != 0 || v != 0) atan2_grid = std::max(atan2_grid, std::abs(g.y - std::atan2(v, u)));
      const double u_small = static_cast<float>(u / 1024.0);
      if (u != 0 || v != 0) atan2_steep = std::max(atan2_steep, std::abs(g.z - std::atan2(u_small, v)));
    }
  }
  EXPECT_LE(atan1, 1.5e-7);
  EXPECT_LE(asin1, 1.7e-7);
  EXPECT_LE(acos1, 3e-7);
  EXPECT_LE(atan2_grid, 3e-7);
  EXPECT_LE(atan2_steep, 3e-7);
  EXPECT_LE(tan_relative, 2.5e-7);
  std::cout << fmt::format("max abs error: atan {:.3g}, asin {:.3g}, acos {:.3g}, atan2 {:.3g} and {:.3g}; tan's "
                           "relative error {:.3g}\n",
                           atan1, asin1, acos1, atan2_grid, atan2_steep, tan_relative);
}


// Integer division and remainder by constants, compiled to multiplies by magic numbers
// (and shifts), against C++ on 262,144 dividends and eight divisors.
TEST(GlslMath, IntegerDivisionByAConstantIsExact) {
  const Image image = render_accuracy_grid("integer_division.rgen");
  const auto dividend = [](std::uint32_t k) -> std::uint32_t {
    if (k == 0) return 0;
    if (k == 8) return 0xffffffffu;
    if (k == 16) return 0x80000000u;
    if (k == 24) return 0x7fffffffu;
    return k * 2654435761u + (k >> 3);
  };
  // SPIR-V's SMod: the remainder with the divisor's sign.
  const auto smod = [](std::int64_t a, std::int64_t d) {
    const std::int64_t r = a % d;
    return r != 0 && (r < 0) != (d < 0) ? r + d : r;
  };
  int wrong = 0;
  for (std::uint32_t k = 0; k < 512 * 512; ++k) {
    const std::uint32_t a = dividend(k & ~7u);
    const std::int64_t i = static_cast<std::int32_t>(a);
    std::int64_t q = 0, r = 0;
    switch (k & 7u) {
      case 0: q = a / 3u, r = a % 3u; break;
      case 1: q = a / 7u, r = a % 7u; break;
      case 2: q = a / 1000u, r = a % 1000u; break;
      case 3: q = a / 0xfffffffbu, r = a % 0xfffffffbu; break;
      case 4: q = i / 10, r = smod(i, 10); break;
      case 5: q = i / -7, r = smod(i, -7); break;
      case 6: q = i / 641, r = smod(i, -641); break;
      default: q = i / -2147483648LL, r = smod(i, 6700417); break;
    }
    const auto qu = static_cast<std::uint32_t>(q), ru = static_cast<std::uint32_t>(r);
    const glm::vec3 want(static_cast<float>(qu & 0xffffu), static_cast<float>(qu >> 16), static_cast<float>(ru & 0xffffu));
    const glm::vec3 have = image.at(static_cast<int>(k % 512), static_cast<int>(k / 512));
    if (have != want && ++wrong <= 5) {
      ADD_FAILURE() << fmt::format("case {} of a = {:#010x}: quotient {:#x}, remainder {:#x}; the shader gave ({}, {}, {})",
                                   k & 7u, a, qu, ru, have.x, have.y, have.z);
    }
  }
  EXPECT_EQ(wrong, 0);
}


// Integer division and remainder by divisors known only when the shader runs (a loop of
// 32 restoring steps), against C++ on 65,536 pairs.
TEST(GlslMath, IntegerDivisionByAVariableIsExact) {
  const Image image = render_accuracy_grid("integer_division_variable.rgen");
  const auto smod = [](std::int64_t a, std::int64_t d) {
    const std::int64_t r = a % d;
    return r != 0 && (r < 0) != (d < 0) ? r + d : r;
  };
  int wrong = 0;
  for (std::uint32_t k = 0; k < 512 * 512; ++k) {
    const std::uint32_t g = k >> 2;
    std::uint32_t a = 0, d = 0;
    if (g < 16) {
      a = g < 4 ? 0u : g < 8 ? 1u : g < 12 ? 0x80000000u : 0xffffffffu;
      d = std::array<std::uint32_t, 4>{1u, 3u, 0x80000000u, 0xffffffffu}[g & 3];
    } else {
      a = g * 2654435761u + (g >> 3);
      d = ((g ^ 0x5bd1e995u) * 0x27d4eb2du) >> (g % 31);
      if (d == 0) d = 7;
    }
    std::int64_t q = 0, r = 0;
    if ((k & 1) == 0) {
      q = a / d, r = a % d;
    } else {
      const std::int64_t i = static_cast<std::int32_t>(a), j = static_cast<std::int32_t>(d);
      q = i / j, r = smod(i, j);
    }
    const auto qu = static_cast<std::uint32_t>(q), ru = static_cast<std::uint32_t>(r);
    const glm::vec3 want(static_cast<float>(qu & 0xffffu), static_cast<float>(qu >> 16), static_cast<float>(ru & 0xffffu));
    const glm::vec3 have = image.at(static_cast<int>(k % 512), static_cast<int>(k / 512));
    if (have != want && ++wrong <= 5) {
      ADD_FAILURE() << fmt::format("{} {:#010x} / {:#010x}: quotient {:#x}, remainder {:#x}; the shader gave ({}, {}, {})",
                                   (k & 1) ? "signed" : "unsigned", a, d, qu, ru, have.x, have.y, have.z);
    }
  }
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace rpu
