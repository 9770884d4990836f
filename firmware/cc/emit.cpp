#include "cc/emit.hpp"

#include <fmt/format.h>

namespace rpu::cc {

namespace {

constexpr char kLanes[] = "xyzw";

std::string swizzle_text(std::array<int, 4> swz) {
  // Unset positions take the nearest set one to their left (or the first set one).
  int first = -1;
  for (int p = 0; p < 4; ++p) {
    if (swz[static_cast<std::size_t>(p)] >= 0) {
      first = swz[static_cast<std::size_t>(p)];
      break;
    }
  }
  if (first < 0) first = 0;
  int last = first;
  for (int& s : swz) {
    if (s < 0) s = last;
    last = s;
  }
  std::string t;
  for (int s : swz) t += kLanes[s];
  if (t == "xyzw") return "";
  while (t.size() > 1 && t[t.size() - 1] == t[t.size() - 2]) t.pop_back();
  return "." + t;
}

class Emitter {
 public:
  Emitter(const MFunction& f, const Allocation& a) : f_(f), a_(a) {}

  std::string run() {
    for (std::size_t i = 0; i < f_.code.size(); ++i) instruction(i);
    return out_;
  }

 private:
  const Location& loc(int v) const { return a_.location.at(static_cast<std::size_t>(v)); }
  int width(int v) const { return f_.vregs.at(static_cast<std::size_t>(v)).width; }

  // The machine lanes a write to `dst` touches, in component order.
  std::vector<int> dst_lanes(const MInst& m) const {
    std::vector<int> lanes;
    const int w = width(m.dst);
    for (int j = 0; j < w; ++j) {
      if (m.dst_comps == 0 || (m.dst_comps >> j) & 1u) lanes.push_back(loc(m.dst).lane[static_cast<std::size_t>(j)]);
    }
    return lanes;
  }
  static std::string mask_text(const std::vector<int>& lanes) {
    int mask = 0;
    for (int l : lanes) mask |= 1 << l;
    if (mask == 0xf) return "";
    std::string t = ".";
    for (int l = 0; l < 4; ++l) {
      if ((mask >> l) & 1) t += kLanes[l];
    }
    return t;
  }
  std::string reg_text(const Src& s, const std::array<int, 4>& swz) const {
    std::string r = fmt::format("r{}", loc(s.v).reg);
    if (s.abs) r = "|" + r + "|";
    if (s.neg) r = "-" + r;
    return r + swizzle_text(swz);
  }
  std::string lanewise(const Src& s, const std::vector<int>& lanes) const {
    std::array<int, 4> swz{-1, -1, -1, -1};
    for (std::size_t k = 0; k < lanes.size(); ++k) {
      const int e = std::min(static_cast<int>(k), s.n - 1);
      swz[static_cast<std::size_t>(lanes[k])] = loc(s.v).lane[s.comp[static_cast<std::size_t>(e)]];
    }
    return reg_text(s, swz);
  }
  std::string positional(const Src& s) const {
    std::array<int, 4> swz{-1, -1, -1, -1};
    for (int j = 0; j < s.n; ++j) swz[static_cast<std::size_t>(j)] = loc(s.v).lane[s.comp[static_cast<std::size_t>(j)]];
    return reg_text(s, swz);
  }
  std::string address(const MInst& m) const {
    const Src& a = m.srcs[0];
    const std::string r = fmt::format("r{}{}", loc(a.v).reg, swizzle_text({loc(a.v).lane[a.comp[0]], -1, -1, -1}));
    const long long off = std::stoll(m.imm.empty() ? "0" : m.imm, nullptr, 0);
    if (off == 0) return "[" + r + "]";
    return off < 0 ? fmt::format("[{} - {}]", r, -off) : fmt::format("[{} + {}]", r, off);
  }
  void line(const MInst& m, const std::string& text) {
    if (m.where.line > 0 && (m.where.line != last_line_ || m.where.file != last_file_)) {
      out_ += fmt::format("        ; {}:{}\n", m.where.file, m.where.line);
      last_line_ = m.where.line;
      last_file_ = m.where.file;
    }
    out_ += "        " + text + "\n";
  }
  // Is the next instruction that emits code a label `target` (so a bra to it falls through)?
  bool falls_to(std::size_t i, const std::string& target) const {
    for (std::size_t k = i + 1; k < f_.code.size(); ++k) {
      if (f_.code[k].kind != Kind::kLabel) return false;
      if (f_.code[k].target == target) return true;
    }
    return false;
  }

  void instruction(std::size_t i) {
    const MInst& m = f_.code[i];
    switch (m.kind) {
      case Kind::kEntry: return;
      case Kind::kLabel: out_ += m.target + ":\n"; return;
      case Kind::kBranch:
        if (!falls_to(i, m.target)) line(m, "bra     " + m.target);
        return;
      case Kind::kCondBranch: line(m, fmt::format("{:<7} {}, {}", m.mn, positional(m.srcs[0]), m.target)); return;
      case Kind::kRet: line(m, "ret"); return;
      case Kind::kHalt: line(m, "halt"); return;
      case Kind::kCall: {
        const auto& saves = a_.saves[i];
        for (const SavedRegister& s : saves) line(m, fmt::format("push    r{}", s.reg));
        line(m, "call    " + m.target);
        for (auto it = saves.rbegin(); it != saves.rend(); ++it) {
          std::vector<int> lanes;
          for (int l = 0; l < 4; ++l) {
            if ((it->lanes >> l) & 1) lanes.push_back(l);
          }
          line(m, fmt::format("pop     r{}{}", it->reg, mask_text(lanes)));
        }
        return;
      }
      case Kind::kSpill:
        // A vector lives in lanes x.. wherever it is; a scalar may come back in another
        // lane than it left from, so it is pushed to all four.
        line(m, fmt::format("{:<39} ; spill", "push    " + (width(m.srcs[0].v) == 1 ? positional(m.srcs[0])
                                                                      : fmt::format("r{}", loc(m.srcs[0].v).reg))));
        return;
      case Kind::kReload:
        line(m, fmt::format("{:<39} ; reload", fmt::format("pop     r{}{}", loc(m.dst).reg, mask_text(dst_lanes(m)))));
        return;
      case Kind::kOp: break;
    }
    if (m.store) {
      const Src& v = m.srcs[1];
      std::vector<int> lanes;
      for (int j = 0; j < v.n; ++j) lanes.push_back(j);
      line(m, fmt::format("{:<7} {}, r{}{}", m.mn, address(m), loc(v.v).reg, mask_text(lanes)));
      return;
    }
    std::vector<std::string> operands;
    std::vector<int> lanes;
    if (m.dst >= 0) {
      lanes = dst_lanes(m);
      operands.push_back(fmt::format("r{}{}", loc(m.dst).reg, mask_text(lanes)));
    }
    if (m.mem) {
      operands.push_back(address(m));
    } else {
      for (const Src& s : m.srcs) {
        operands.push_back(m.shape == Shape::kPositional || m.dst < 0 ? positional(s) : lanewise(s, lanes));
      }
      if (!m.imm.empty()) operands.push_back(m.imm);
    }
    // A copy onto itself is no instruction.
    if (m.mn == "mov" && m.dst >= 0 && !m.srcs[0].neg && !m.srcs[0].abs && loc(m.srcs[0].v).reg == loc(m.dst).reg) {
      bool same = true;
      for (std::size_t k = 0; k < lanes.size(); ++k) {
        const int e = std::min(static_cast<int>(k), m.srcs[0].n - 1);
        same = same && loc(m.srcs[0].v).lane[m.srcs[0].comp[static_cast<std::size_t>(e)]] == lanes[k];
      }
      if (same) return;
    }
    std::string text = fmt::format("{:<7}", m.mn);
    for (std::size_t k = 0; k < operands.size(); ++k) text += (k ? ", " : " ") + operands[k];
    while (!text.empty() && text.back() == ' ') text.pop_back();
    line(m, text);
  }

  const MFunction& f_;
  const Allocation& a_;
  std::string out_;
  int last_line_ = -1;
  std::string last_file_;
};

}  // namespace

std::string emit(const MFunction& function, const Allocation& allocation) {
  return Emitter(function, allocation).run();
}

}  // namespace rpu::cc
