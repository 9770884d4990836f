// Random GLSL programs (docs/shaders.md "Tests"): generated straight-line code, branches
// and loops over float and int variables, compiled by rpu cc at -O0 and -O2 and run on
// the functional device, against the same program evaluated on the host with the chip's
// arithmetic (fp32 with subnormals flushed, division as a * (1/b), inversesqrt as
// 1/sqrt, fma fused, min/max with -0 < +0). A failing program is shrunk (statements
// dropped, expressions replaced by their operands) while it still fails, and the
// smallest is printed with its seed.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>

#include <fmt/format.h>

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

constexpr int kVars = 4;      // float variables v0..v3
constexpr int kPixels = 8;    // each pixel runs the program on its own inputs
constexpr int kPrograms = 60;

// ---- the chip's fp32 on the host ------------------------------------------------------
float ftz(float x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }
float chip_min(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::bit_cast<float>(0x7fc00000u);
  return (a < b || (a == b && std::signbit(a))) ? a : b;
}
float chip_max(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::bit_cast<float>(0x7fc00000u);
  return (a > b || (a == b && !std::signbit(a))) ? a : b;
}

// ---- programs ---------------------------------------------------------------------------
struct Expr {
  enum Op { kVar, kConst, kLoop, kAdd, kSub, kMul, kDiv, kMin, kMax, kFma, kSelect, kAbs, kNeg, kFloor, kSqrt, kRsq };
  Op op = kConst;
  int var = 0;
  float value = 0.0f;
  std::vector<Expr> kids;
};

struct Stmt {
  enum Kind { kAssign, kIf, kLoop } kind = kAssign;
  int target = 0;
  Expr value;            // assign: the value; if: the left side of <
  Expr right;            // if: the right side of <
  std::vector<Stmt> body, orelse;
  int trips = 0;         // loop
};

struct Program {
  std::array<float, kVars> offsets{};
  std::vector<Stmt> body;
};

class Generator {
 public:
  explicit Generator(std::uint32_t seed) : rng_(seed) {}

  Program program() {
    Program p;
    for (float& o : p.offsets) o = constant();
    const int n = pick(2, 6);
    for (int k = 0; k < n; ++k) p.body.push_back(statement(2, false));
    return p;
  }

 private:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  float constant() {
    static constexpr float kValues[] = {0.0f, 1.0f, -1.0f, 0.5f, 2.0f, -3.0f, 0.25f, 10.0f, -0.125f, 7.0f, 1.5f, 100.0f};
    return kValues[pick(0, static_cast<int>(std::size(kValues)) - 1)];
  }
  Expr expr(int depth, bool in_loop) {
    Expr e;
    if (depth == 0 || pick(0, 3) == 0) {
      const int leaf = pick(0, in_loop ? 5 : 4);
      if (leaf <= 2) {
        e.op = Expr::kVar;
        e.var = pick(0, kVars - 1);
      } else if (leaf <= 4) {
        e.op = Expr::kConst;
        e.value = constant();
      } else {
        e.op = Expr::kLoop;
      }
      return e;
    }
    e.op = static_cast<Expr::Op>(pick(Expr::kAdd, Expr::kRsq));
    const int arity = e.op >= Expr::kAbs ? 1 : e.op == Expr::kFma || e.op == Expr::kSelect ? 3 : 2;
    for (int k = 0; k < arity + (e.op == Expr::kSelect ? 1 : 0); ++k) e.kids.push_back(expr(depth - 1, in_loop));
    // Every operation reads a variable: SPIRV-Tools folds constant operations at compile
    // time with exact division, which the chip does not have (docs/shaders.md).
    if (!reads_variable(e)) {
      e.kids[0] = Expr{};
      e.kids[0].op = Expr::kVar;
      e.kids[0].var = pick(0, kVars - 1);
    }
    return e;
  }
  static bool reads_variable(const Expr& e) {
    if (e.op == Expr::kVar) return true;
    for (const Expr& k : e.kids) {
      if (reads_variable(k)) return true;
    }
    return false;
  }
  Stmt statement(int depth, bool in_loop) {
    Stmt s;
    const int kind = depth == 0 ? 0 : pick(0, 5);
    s.target = pick(0, kVars - 1);
    if (kind <= 3) {
      s.value = expr(3, in_loop);
    } else if (kind == 4) {
      s.kind = Stmt::kIf;
      s.value = expr(2, in_loop);
      s.right = expr(2, in_loop);
      for (int k = pick(1, 3); k > 0; --k) s.body.push_back(statement(depth - 1, in_loop));
      for (int k = pick(0, 2); k > 0; --k) s.orelse.push_back(statement(depth - 1, in_loop));
    } else if (!in_loop) {
      s.kind = Stmt::kLoop;
      s.trips = pick(1, 4);
      for (int k = pick(1, 3); k > 0; --k) s.body.push_back(statement(depth - 1, true));
    } else {
      s.value = expr(3, in_loop);
    }
    return s;
  }
  std::mt19937 rng_;
};

// ---- GLSL ---------------------------------------------------------------------------------
std::string glsl_float(float v) {
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string glsl(const Expr& e) {
  const auto k = [&](std::size_t i) { return glsl(e.kids[i]); };
  switch (e.op) {
    case Expr::kVar: return fmt::format("v{}", e.var);
    case Expr::kConst: return glsl_float(e.value);
    case Expr::kLoop: return "float(i)";
    case Expr::kAdd: return fmt::format("({} + {})", k(0), k(1));
    case Expr::kSub: return fmt::format("({} - {})", k(0), k(1));
    case Expr::kMul: return fmt::format("({} * {})", k(0), k(1));
    case Expr::kDiv: return fmt::format("({} / {})", k(0), k(1));
    case Expr::kMin: return fmt::format("min({}, {})", k(0), k(1));
    case Expr::kMax: return fmt::format("max({}, {})", k(0), k(1));
    case Expr::kFma: return fmt::format("fma({}, {}, {})", k(0), k(1), k(2));
    case Expr::kSelect: return fmt::format("({} < {} ? {} : {})", k(0), k(1), k(2), k(3));
    case Expr::kAbs: return fmt::format("abs({})", k(0));
    case Expr::kNeg: return fmt::format("(-{})", k(0));
    case Expr::kFloor: return fmt::format("floor({})", k(0));
    case Expr::kSqrt: return fmt::format("sqrt(abs({}))", k(0));
    case Expr::kRsq: return fmt::format("inversesqrt(abs({}))", k(0));
  }
  return "";
}

void glsl(const std::vector<Stmt>& body, int indent, std::string& out) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  for (const Stmt& s : body) {
    if (s.kind == Stmt::kAssign) {
      out += fmt::format("{}v{} = {};\n", pad, s.target, glsl(s.value));
    } else if (s.kind == Stmt::kIf) {
      out += fmt::format("{}if ({} < {}) {{\n", pad, glsl(s.value), glsl(s.right));
      glsl(s.body, indent + 2, out);
      if (!s.orelse.empty()) {
        out += pad + "} else {\n";
        glsl(s.orelse, indent + 2, out);
      }
      out += pad + "}\n";
    } else {
      out += fmt::format("{}for (int i = 0; i < {}; ++i) {{\n", pad, s.trips);
      glsl(s.body, indent + 2, out);
      out += pad + "}\n";
    }
  }
}

// The program as a ray generation shader: pixel x's inputs are x + offset; v0..v2 go to
// its framebuffer pixel. `precise` keeps SPIRV-Tools from fusing a * b + c.
std::string glsl(const Program& p) {
  std::string out =
      "#version 460\n#extension GL_EXT_ray_tracing : require\n#include \"rpu.glsl\"\nvoid main() {\n"
      "  const float x = float(gl_LaunchIDEXT.x);\n";
  for (int k = 0; k < kVars; ++k) out += fmt::format("  precise float v{} = x + {};\n", k, glsl_float(p.offsets[k]));
  glsl(p.body, 2, out);
  out += "  imageStore(framebuffer, ivec2(gl_LaunchIDEXT.xy), vec4(v0, v1, v2 + v3, 1.0));\n}\n";
  return out;
}

// ---- the host's evaluation ------------------------------------------------------------------
struct State {
  std::array<float, kVars> v{};
  int loop = 0;
};

float eval(const Expr& e, const State& s) {
  const auto k = [&](std::size_t i) { return ftz(eval(e.kids[i], s)); };
  switch (e.op) {
    case Expr::kVar: return s.v[static_cast<std::size_t>(e.var)];
    case Expr::kConst: return e.value;
    case Expr::kLoop: return static_cast<float>(s.loop);
    case Expr::kAdd: return ftz(k(0) + k(1));
    case Expr::kSub: return ftz(k(0) - k(1));
    case Expr::kMul: return ftz(k(0) * k(1));
    case Expr::kDiv: return ftz(k(0) * ftz(1.0f / k(1)));
    case Expr::kMin: return chip_min(k(0), k(1));
    case Expr::kMax: return chip_max(k(0), k(1));
    case Expr::kFma: return ftz(std::fma(k(0), k(1), k(2)));
    case Expr::kSelect: return k(0) < k(1) ? k(2) : k(3);
    case Expr::kAbs: return std::fabs(k(0));
    case Expr::kNeg: return -k(0);
    case Expr::kFloor: return std::floor(k(0));
    case Expr::kSqrt: return ftz(std::sqrt(std::fabs(k(0))));
    case Expr::kRsq: return ftz(1.0f / ftz(std::sqrt(std::fabs(k(0)))));
  }
  return 0.0f;
}

void run(const std::vector<Stmt>& body, State& s) {
  for (const Stmt& st : body) {
    if (st.kind == Stmt::kAssign) {
      s.v[static_cast<std::size_t>(st.target)] = eval(st.value, s);
    } else if (st.kind == Stmt::kIf) {
      run(ftz(eval(st.value, s)) < ftz(eval(st.right, s)) ? st.body : st.orelse, s);
    } else {
      const int outer = s.loop;
      for (int i = 0; i < st.trips; ++i) {
        s.loop = i;
        run(st.body, s);
      }
      s.loop = outer;
    }
  }
}

std::array<float, 3> expected(const Program& p, int x) {
  State s;
  for (int k = 0; k < kVars; ++k) s.v[static_cast<std::size_t>(k)] = ftz(static_cast<float>(x) + p.offsets[static_cast<std::size_t>(k)]);
  run(p.body, s);
  return {s.v[0], s.v[1], ftz(s.v[2] + s.v[3])};
}

bool same(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (std::isnan(a) && std::isnan(b));
}

// ---- running on the device ------------------------------------------------------------------
class Runner {
 public:
  Runner()
      : config_(hardware_config("tiny")),
        scene_(resolve_scene("tetra:1")),
        si_(functional::make_scene_image(scene_, kd_build_config_for(std::string(config_.name)), IsectMode::kWoop)) {}

  // Empty if the device agrees with the host at both optimisation levels, else what differs.
  std::string mismatch(const Program& p) const {
    const std::string source = glsl(p);
    for (const int level : {0, 2}) {
      cc::CompileOptions options;
      options.opt_level = level;
      isa::Firmware fw;
      try {
        fw = cc::compile({{"random.rgen", source}, {"whitted.rchit", kEmptyHit}}, options).firmware;
      } catch (const Error& e) {
        return fmt::format("-O{}: does not compile: {}", level, e.what());
      }
      RenderSettings settings;
      settings.width = kPixels;
      settings.height = 1;
      settings.spp = 1;
      settings.max_depth = 0;
      settings.threads = 1;
      const auto dev = device::make_functional_device(config_, fp::kFp32);
      Image image;
      try {
        image = device::render_frame(*dev, scene_, si_.image, fw, settings);
      } catch (const std::exception& e) {
        return fmt::format("-O{}: the run fails: {}", level, e.what());
      }
      for (int x = 0; x < kPixels; ++x) {
        const std::array<float, 3> want = expected(p, x);
        const glm::vec3 got = image.at(x, 0);
        for (int c = 0; c < 3; ++c) {
          if (!same(got[c], want[static_cast<std::size_t>(c)])) {
            return fmt::format("-O{}: pixel {} {} is {} ({:#010x}), the host says {} ({:#010x})", level, x, "rgb"[c],
                               got[c], std::bit_cast<std::uint32_t>(got[c]), want[static_cast<std::size_t>(c)],
                               std::bit_cast<std::uint32_t>(want[static_cast<std::size_t>(c)]));
          }
        }
      }
    }
    return {};
  }

 private:
  static constexpr const char* kEmptyHit = "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n";
  const spec::HardwareConfig& config_;
  Scene scene_;
  functional::SceneImage si_;
};

// ---- shrinking ----------------------------------------------------------------------------------
// Candidates one step smaller: a statement dropped, a branch or loop replaced by its body,
// an expression replaced by one of its operands or a constant.
void smaller_exprs(const Expr& e, const std::function<void(const Expr&)>& emit) {
  for (const Expr& k : e.kids) emit(k);
  if (e.op != Expr::kConst) {
    Expr c;
    c.value = 1.0f;
    emit(c);
  }
  for (std::size_t i = 0; i < e.kids.size(); ++i) {
    smaller_exprs(e.kids[i], [&](const Expr& k) {
      Expr copy = e;
      copy.kids[i] = k;
      emit(copy);
    });
  }
}

void smaller_bodies(const std::vector<Stmt>& body, const std::function<void(const std::vector<Stmt>&)>& emit) {
  for (std::size_t i = 0; i < body.size(); ++i) {
    std::vector<Stmt> copy = body;
    copy.erase(copy.begin() + static_cast<std::ptrdiff_t>(i));
    emit(copy);
    if (body[i].kind != Stmt::kAssign) {
      copy = body;
      copy.erase(copy.begin() + static_cast<std::ptrdiff_t>(i));
      copy.insert(copy.begin() + static_cast<std::ptrdiff_t>(i), body[i].body.begin(), body[i].body.end());
      emit(copy);
    }
    const auto with = [&](const Stmt& s) {
      std::vector<Stmt> c = body;
      c[i] = s;
      emit(c);
    };
    smaller_exprs(body[i].value, [&](const Expr& e) {
      Stmt s = body[i];
      s.value = e;
      with(s);
    });
    if (body[i].kind == Stmt::kIf) {
      smaller_exprs(body[i].right, [&](const Expr& e) {
        Stmt s = body[i];
        s.right = e;
        with(s);
      });
    }
    smaller_bodies(body[i].body, [&](const std::vector<Stmt>& b) {
      Stmt s = body[i];
      s.body = b;
      with(s);
    });
    smaller_bodies(body[i].orelse, [&](const std::vector<Stmt>& b) {
      Stmt s = body[i];
      s.orelse = b;
      with(s);
    });
  }
}

// The smallest program reachable by one-step reductions that still `fails`.
Program shrink(Program p, const std::function<bool(const Program&)>& fails) {
  for (bool progress = true; progress;) {
    progress = false;
    std::vector<std::vector<Stmt>> candidates;
    smaller_bodies(p.body, [&](const std::vector<Stmt>& b) { candidates.push_back(b); });
    for (const auto& c : candidates) {
      Program q = p;
      q.body = c;
      if (fails(q)) {
        p = q;
        progress = true;
        break;
      }
    }
  }
  return p;
}

TEST(GlslRandomPrograms, TheDeviceComputesWhatTheHostComputes) {
  const Runner runner;
  for (std::uint32_t seed = 1; seed <= kPrograms; ++seed) {
    const Program p = Generator(seed).program();
    const std::string why = runner.mismatch(p);
    if (why.empty()) continue;
    const Program small = shrink(p, [&](const Program& q) { return !runner.mismatch(q).empty(); });
    ADD_FAILURE() << fmt::format("seed {}: {}\nshrunk to ({}):\n{}", seed, why, runner.mismatch(small), glsl(small));
    return;
  }
}

// The shrinker's own test: a "bug" that only the host's division shows (the host divides
// exactly here, unlike the chip) shrinks to a program with one division left.
TEST(GlslRandomPrograms, TheShrinkerKeepsTheFailure) {
  Expr a;
  a.op = Expr::kVar;
  Expr third;
  third.value = 3.0f;
  Expr div;
  div.op = Expr::kDiv;
  div.kids = {a, third};
  Program p;
  p.offsets = {0.1f, 1.0f, 2.0f, 3.0f};
  Stmt s;
  s.value = div;
  Stmt noise;
  noise.target = 1;
  noise.value = third;
  p.body = {noise, s, noise};
  // The host side of this check divides exactly: a mismatch exists iff a * (1/3) != a / 3.
  const auto fails = [](const Program& q) {
    for (int x = 0; x < kPixels; ++x) {
      State st;
      for (int k = 0; k < kVars; ++k) st.v[static_cast<std::size_t>(k)] = static_cast<float>(x) + q.offsets[static_cast<std::size_t>(k)];
      State exact = st;
      run(q.body, st);
      for (const Stmt& t : q.body) {
        if (t.kind == Stmt::kAssign && t.value.op == Expr::kDiv) {
          exact.v[static_cast<std::size_t>(t.target)] = eval(t.value.kids[0], exact) / eval(t.value.kids[1], exact);
        } else if (t.kind == Stmt::kAssign) {
          exact.v[static_cast<std::size_t>(t.target)] = eval(t.value, exact);
        }
      }
      if (!same(st.v[0], exact.v[0])) return true;
    }
    return false;
  };
  ASSERT_TRUE(fails(p));
  p = shrink(p, fails);
  ASSERT_EQ(p.body.size(), 1u) << glsl(p);
  EXPECT_EQ(p.body[0].value.op, Expr::kDiv) << glsl(p);
}

}  // namespace
}  // namespace rpu
