#include "cc/builder.hpp"

#include <bit>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu::cc {

int Builder::vreg(int width) {
  fn_.vregs.push_back({width});
  return static_cast<int>(fn_.vregs.size()) - 1;
}

int Builder::fixed(int width, int reg, int lane) {
  fn_.vregs.push_back({width, reg, lane});
  return static_cast<int>(fn_.vregs.size()) - 1;
}

MInst& Builder::push(MInst i) {
  i.where = where;
  if (i.kind == Kind::kOp || i.kind == Kind::kCondBranch) {
    const bool mods = isa::find_insn(i.op)->float_modifiers;
    for (std::size_t k = 0; k < i.srcs.size(); ++k) {
      Src& s = i.srcs[k];
      if (!(s.neg || s.abs) || (mods && !(k == 2 && s.abs))) continue;
      MInst m;
      m.op = Opcode::kMov;
      m.dst = vreg(s.n);
      m.srcs = {s};
      m.where = where;
      fn_.code.push_back(m);
      s = cc::whole(m.dst, s.n);
    }
  }
  fn_.code.push_back(std::move(i));
  return fn_.code.back();
}

Src Builder::op(Opcode opcode, int width, std::vector<Src> srcs, Imm imm) {
  const int d = vreg(width);
  op_into(d, 0, opcode, std::move(srcs), imm);
  return cc::whole(d, width);
}

void Builder::op_into(int dst, std::uint8_t comps, Opcode opcode, std::vector<Src> srcs, Imm imm, bool fresh) {
  MInst i;
  i.op = opcode;
  i.dst = dst;
  i.dst_comps = comps;
  i.fresh = fresh;
  i.srcs = std::move(srcs);
  i.imm = imm;
  push(std::move(i));
}

void Builder::copy_into(int dst, const Src& from) { op_into(dst, 0, Opcode::kMov, {from}); }

Src Builder::constant(std::uint32_t bits, bool is_float, int width) {
  return op(is_float ? Opcode::kLif : Opcode::kLi, width, {}, Imm::lane(bits, is_float));
}

Src Builder::fconst(float f, int width) { return constant(std::bit_cast<std::uint32_t>(f), true, width); }

Src Builder::not_of(const Src& s) { return op(Opcode::kXori, s.n, {s}, Imm::bits(0xffffffffu)); }

Src Builder::select(const Src& cond, const Src& a, const Src& b, int n) {
  return op(Opcode::kSel, n,
            {cond.n == 1 ? broadcast(cond, n) : cond, a.n == 1 && n > 1 ? broadcast(a, n) : a,
             b.n == 1 && n > 1 ? broadcast(b, n) : b});
}

void Builder::label(const std::string& name) {
  MInst i;
  i.kind = Kind::kLabel;
  i.label = name;
  push(std::move(i));
}

void Builder::branch(const std::string& target) {
  MInst b;
  b.kind = Kind::kBranch;
  b.imm = Imm::code_label(target);
  push(std::move(b));
}

std::string Builder::fresh_label(const std::string& stem) { return fmt::format(".{}_{}{}", fn_.label, stem, labels_++); }

void Builder::cond_branch(bool if_nonzero, const Src& cond, const std::string& target) {
  MInst b;
  b.kind = Kind::kCondBranch;
  b.op = if_nonzero ? Opcode::kBnz : Opcode::kBz;
  b.srcs = {component(cond, 0)};
  b.imm = Imm::code_label(target);
  push(std::move(b));
}

void Builder::fail(const SourceLocation& at, const std::string& what) const {
  const std::string file = at.file.empty() ? fn_.name : at.file;
  if (at.line > 0) throw Error(fmt::format("{}:{}: error: {}", file, at.line, what));
  throw Error(fmt::format("{}: error: {}", file, what));
}

void Builder::unsupported(const std::string& what) const {
  fail(where, fmt::format("{} is not supported by the RPU back end (docs/shaders.md \"What compiles\")", what));
}

}  // namespace rpu::cc
