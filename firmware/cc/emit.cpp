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
  // [r + offset]: the base address in lane x of the swizzled register.
  std::string address(const Src& a, const Imm& offset) const {
    const std::string r = fmt::format("r{}{}", loc(a.v).reg, swizzle_text({loc(a.v).lane[a.comp[0]], -1, -1, -1}));
    if (offset.type == Imm::Type::kSymbol) return fmt::format("[{} + {}]", r, offset.symbol->name);
    const std::int64_t off = offset.value;
    if (off == 0) return "[" + r + "]";
    return off < 0 ? fmt::format("[{} - {}]", r, -off) : fmt::format("[{} + {}]", r, off);
  }
  static std::string imm_text(const Imm& imm) {
    switch (imm.type) {
      case Imm::Type::kInteger: return fmt::format("{}", imm.value);
      case Imm::Type::kBits:
      case Imm::Type::kFloat: return fmt::format("{:#x}", imm.field());
      case Imm::Type::kSpecial:
        for (const spec::isa::SpecialSpec& s : spec::isa::kSpecials) {
          if (s.index == imm.value) return std::string(s.name);
        }
        break;
      case Imm::Type::kSymbol: return std::string(imm.symbol->name);
      case Imm::Type::kLabel: return imm.label;
      case Imm::Type::kNone: break;
    }
    return fmt::format("{}", imm.value);
  }
  void line(const MInst& m, const std::string& text, std::string_view note = {}) {
    if (m.where.line > 0 && (m.where.line != last_line_ || m.where.file != last_file_)) {
      out_ += fmt::format("        ; {}:{}\n", m.where.file, m.where.line);
      last_line_ = m.where.line;
      last_file_ = m.where.file;
    }
    out_ += "        " + (note.empty() ? text : fmt::format("{:<39} ; {}", text, note)) + "\n";
  }
  // Is the next instruction that emits code a label `target` (so a bra to it falls through)?
  bool falls_to(std::size_t i, const std::string& target) const {
    for (std::size_t k = i + 1; k < f_.code.size(); ++k) {
      if (f_.code[k].kind != Kind::kLabel) return false;
      if (f_.code[k].label == target) return true;
    }
    return false;
  }

  void instruction(std::size_t i) {
    const MInst& m = f_.code[i];
    switch (m.kind) {
      case Kind::kEntry: return;
      case Kind::kLabel: out_ += m.label + ":\n"; return;
      case Kind::kBranch:
        if (!falls_to(i, m.imm.label)) line(m, "bra     " + m.imm.label);
        return;
      case Kind::kRet: line(m, "ret"); return;
      case Kind::kHalt: line(m, "halt"); return;
      case Kind::kCall: {
        const auto& saves = a_.saves[i];
        for (const SavedRegister& s : saves) line(m, fmt::format("push    r{}", s.reg));
        line(m, "call    " + m.imm.label);
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
        line(m, "push    " + (width(m.srcs[0].v) == 1 ? positional(m.srcs[0]) : fmt::format("r{}", loc(m.srcs[0].v).reg)),
             "spill");
        return;
      case Kind::kReload:
        line(m, fmt::format("pop     r{}{}", loc(m.dst).reg, mask_text(dst_lanes(m))), "reload");
        return;
      case Kind::kOp:
      case Kind::kCondBranch: break;
    }
    // The operands in the order of the opcode's (spec/isa.toml); m.srcs in the same order.
    const isa::InsnSpec& spec = *isa::find_insn(m.op);
    std::vector<std::string> operands;
    const std::vector<int> lanes = m.dst >= 0 ? dst_lanes(m) : std::vector<int>{};
    std::size_t next = 0;
    for (int k = 0; k < spec.operand_count; ++k) {
      switch (spec.operands[static_cast<std::size_t>(k)]) {
        case isa::Operand::kD:
          if (spec.dst_is_data) {
            // a store's data: lanes x.. in place
            const Src& v = m.srcs[next++];
            std::vector<int> data(static_cast<std::size_t>(v.n));
            for (int j = 0; j < v.n; ++j) data[static_cast<std::size_t>(j)] = j;
            operands.push_back(fmt::format("r{}{}", loc(v.v).reg, mask_text(data)));
          } else {
            operands.push_back(fmt::format("r{}{}", loc(m.dst).reg, mask_text(lanes)));
          }
          break;
        case isa::Operand::kA:
        case isa::Operand::kB:
        case isa::Operand::kC: {
          const Src& s = m.srcs[next++];
          operands.push_back(spec.lanewise ? lanewise(s, lanes) : positional(s));
          break;
        }
        case isa::Operand::kMem: {
          const Src& a = m.srcs[next++];
          operands.push_back(address(a, m.imm));
          break;
        }
        case isa::Operand::kImm:
        case isa::Operand::kFimm:
        case isa::Operand::kSr: operands.push_back(imm_text(m.imm)); break;
        case isa::Operand::kTarget: operands.push_back(m.imm.label); break;
      }
    }
    // A copy onto itself is no instruction.
    if (m.op == Opcode::kMov && !m.srcs[0].neg && !m.srcs[0].abs && loc(m.srcs[0].v).reg == loc(m.dst).reg) {
      bool same = true;
      for (std::size_t k = 0; k < lanes.size(); ++k) {
        const int e = std::min(static_cast<int>(k), m.srcs[0].n - 1);
        same = same && loc(m.srcs[0].v).lane[m.srcs[0].comp[static_cast<std::size_t>(e)]] == lanes[k];
      }
      if (same) return;
    }
    std::string text = fmt::format("{:<7}", spec.mnemonic);
    for (std::size_t k = 0; k < operands.size(); ++k) text += (k ? ", " : " ") + operands[k];
    while (!text.empty() && text.back() == ' ') text.pop_back();
    line(m, text, m.note);
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
