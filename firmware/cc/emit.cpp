#include "cc/emit.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace rpu::cc {

namespace {

// The swizzle byte of source lanes per position, -1 where a position is not read:
// such a position takes the nearest read one to its left (or the first read one), so
// that the listing's shortest text (".x" for xxxx, ".zy" for zyyy) reads back to it.
std::uint8_t swizzle_of(std::array<int, 4> swz) {
  const auto first = std::find_if(swz.begin(), swz.end(), [](int s) { return s >= 0; });
  int last = first == swz.end() ? 0 : *first;
  std::uint8_t byte = 0;
  for (std::size_t p = 0; p < 4; ++p) {
    if (swz[p] >= 0) last = swz[p];
    byte = static_cast<std::uint8_t>(byte | last << (2 * p));
  }
  return byte;
}

std::uint8_t mask_of(const std::vector<int>& lanes) {
  std::uint8_t mask = 0;
  for (const int l : lanes) mask = static_cast<std::uint8_t>(mask | 1u << l);
  return mask;
}

class Emitter {
 public:
  Emitter(const MFunction& f, const Allocation& a) : f_(f), a_(a) {}

  std::vector<MachineItem> run() {
    for (std::size_t i = 0; i < f_.code.size(); ++i) instruction(i);
    return std::move(out_);
  }

 private:
  const Location& loc(int v) const { return a_.location.at(static_cast<std::size_t>(v)); }
  int width(int v) const { return f_.vregs.at(static_cast<std::size_t>(v)).width; }
  std::uint8_t reg(int v) const { return static_cast<std::uint8_t>(loc(v).reg); }

  // The machine lanes a write to `dst` touches, in component order.
  std::vector<int> dst_lanes(const MInst& m) const {
    std::vector<int> lanes;
    const int w = width(m.dst);
    for (int j = 0; j < w; ++j) {
      if (m.dst_comps == 0 || (m.dst_comps >> j) & 1u) lanes.push_back(loc(m.dst).lane[static_cast<std::size_t>(j)]);
    }
    return lanes;
  }
  isa::Source source(const Src& s, const std::array<int, 4>& swz) const {
    return {reg(s.v), swizzle_of(swz), s.neg, s.abs};
  }
  // Element k of s feeds the destination lane lanes[k] (the last element the rest).
  isa::Source lanewise(const Src& s, const std::vector<int>& lanes) const {
    std::array<int, 4> swz{-1, -1, -1, -1};
    for (std::size_t k = 0; k < lanes.size(); ++k) {
      const int e = std::min(static_cast<int>(k), s.n - 1);
      swz[static_cast<std::size_t>(lanes[k])] = loc(s.v).lane[s.comp[static_cast<std::size_t>(e)]];
    }
    return source(s, swz);
  }
  // Element j of s at position j.
  isa::Source positional(const Src& s) const {
    std::array<int, 4> swz{-1, -1, -1, -1};
    for (int j = 0; j < s.n; ++j) swz[static_cast<std::size_t>(j)] = loc(s.v).lane[s.comp[static_cast<std::size_t>(j)]];
    return source(s, swz);
  }
  // A whole register, lanes in place (what push and pop move).
  static isa::Source whole_register(int r) {
    return {static_cast<std::uint8_t>(r), isa::kIdentitySwizzle, false, false};
  }

  void put(const MInst& m, Opcode op, isa::Instruction insn, Imm imm = {}, std::string_view note = {}) {
    insn.spec = isa::find_insn(op);
    if (imm.type != Imm::Type::kLabel) insn.imm = imm.field();
    out_.emplace_back(MachineInstruction{insn, std::move(imm), m.where, note});
  }
  void put_push(const MInst& m, const isa::Source& s, std::string_view note = {}) {
    isa::Instruction insn;
    insn.src[0] = s;
    put(m, Opcode::kPush, insn, {}, note);
  }
  void put_pop(const MInst& m, int r, std::uint8_t lanes, std::string_view note = {}) {
    isa::Instruction insn;
    insn.dst = static_cast<std::uint8_t>(r);
    insn.wmask = lanes;
    put(m, Opcode::kPop, insn, {}, note);
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
      case Kind::kLabel: out_.emplace_back(Label{m.label, {}}); return;
      case Kind::kBranch:
        if (!falls_to(i, m.imm.label)) put(m, Opcode::kBra, {}, m.imm);
        return;
      case Kind::kRet: put(m, Opcode::kRet, {}); return;
      case Kind::kHalt: put(m, Opcode::kHalt, {}); return;
      case Kind::kTrap: out_.emplace_back(IllegalWord{m.where}); return;
      case Kind::kCall: {
        // What lives across the call: every register is the callee's.
        const auto& saves = a_.saves[i];
        for (const SavedRegister& s : saves) put_push(m, whole_register(s.reg));
        put(m, Opcode::kCall, {}, m.imm);
        for (auto it = saves.rbegin(); it != saves.rend(); ++it) put_pop(m, it->reg, it->lanes);
        return;
      }
      case Kind::kSpill: {
        // A vector lives in lanes x.. wherever it is; a scalar may come back in another
        // lane than it left from, so it is pushed to all four.
        const Src& s = m.srcs[0];
        put_push(m, width(s.v) == 1 ? positional(s) : whole_register(loc(s.v).reg), "spill");
        return;
      }
      case Kind::kReload: put_pop(m, loc(m.dst).reg, mask_of(dst_lanes(m)), "reload"); return;
      case Kind::kOp:
      case Kind::kCondBranch: break;
    }
    // The operands in the order of the opcode's (spec/isa.toml); m.srcs in the same order.
    const isa::InsnSpec& spec = *isa::find_insn(m.op);
    const std::vector<int> lanes = m.dst >= 0 ? dst_lanes(m) : std::vector<int>{};
    isa::Instruction insn;
    std::size_t next = 0;
    for (int k = 0; k < spec.operand_count; ++k) {
      switch (const isa::Operand operand = spec.operands[static_cast<std::size_t>(k)]) {
        case isa::Operand::kD:
          if (spec.dst_is_data) {
            // a store's data: its lanes x.. in place
            const Src& v = m.srcs[next++];
            insn.dst = reg(v.v);
            insn.wmask = static_cast<std::uint8_t>((1u << v.n) - 1);
          } else {
            insn.dst = reg(m.dst);
            insn.wmask = mask_of(lanes);
          }
          break;
        case isa::Operand::kA:
        case isa::Operand::kB:
        case isa::Operand::kC: {
          const Src& s = m.srcs[next++];
          insn.src[static_cast<std::size_t>(operand) - static_cast<std::size_t>(isa::Operand::kA)] =
              spec.lanewise ? lanewise(s, lanes) : positional(s);
          break;
        }
        case isa::Operand::kMem: insn.src[0] = positional(component(m.srcs[next++], 0)); break;
        case isa::Operand::kImm:
        case isa::Operand::kFimm:
        case isa::Operand::kSr:
        case isa::Operand::kTarget: break;  // the immediate, below
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
    put(m, m.op, insn, m.imm, m.note);
  }

  const MFunction& f_;
  const Allocation& a_;
  std::vector<MachineItem> out_;
};

}  // namespace

std::vector<MachineItem> emit(const MFunction& function, const Allocation& allocation) {
  return Emitter(function, allocation).run();
}

}  // namespace rpu::cc
