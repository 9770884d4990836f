// Writing the machine IR of one function: virtual registers, instructions and labels,
// each instruction at the source line being lowered. Lowering, selection, the math
// library and the ABI all write code through a Builder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cc/mir.hpp"

namespace rpu::cc {

class Builder {
 public:
  explicit Builder(MFunction& function) : fn_(function) {}

  // The source line of the instructions made now, and of the refusals.
  SourceLocation where;

  int vreg(int width);
  int fixed(int width, int reg, int lane = 0);  // pinned to a machine register (the ABI's)
  int width(int v) const { return fn_.vregs[static_cast<std::size_t>(v)].width; }
  Src whole(int v) const { return cc::whole(v, width(v)); }

  // Appends `i` at `where`. Where a source has neg or abs that the opcode does not take
  // (spec/isa.toml `mods`, and never abs on a third source), the value is made by a mov
  // first.
  MInst& push(MInst i);
  // dst = opcode srcs, a new vreg of `width` lanes.
  Src op(Opcode opcode, int width, std::vector<Src> srcs, Imm imm = {});
  // dst[comps] = opcode srcs: a partial write into an existing vreg (comps 0: all of it).
  // fresh: the first write of a vreg whose other lanes are never read (not a use of it).
  void op_into(int dst, std::uint8_t comps, Opcode opcode, std::vector<Src> srcs, Imm imm = {}, bool fresh = false);
  void copy_into(int dst, const Src& from);

  // A constant in every lane: fp32 bits (lif) or raw bits (li).
  Src constant(std::uint32_t bits, bool is_float, int width = 1);
  Src fconst(float f, int width = 1);
  // The complement of a mask.
  Src not_of(const Src& s);
  // cond ? a : b per lane, a scalar operand broadcast to n lanes.
  Src select(const Src& cond, const Src& a, const Src& b, int n);

  void label(const std::string& name);
  // A label of this function no other has: its name, the stem and a count.
  std::string fresh_label(const std::string& stem);
  void branch(const std::string& target);
  void cond_branch(bool if_nonzero, const Src& cond, const std::string& target);

  // Errors name the source line (`at`, else the function's file).
  [[noreturn]] void fail(const SourceLocation& at, const std::string& what) const;
  [[noreturn]] void unsupported(const std::string& what) const;

 private:
  MFunction& fn_;
  int labels_ = 0;
};

}  // namespace rpu::cc
