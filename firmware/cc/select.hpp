// Instruction selection: the SPIR-V instructions that compute a scalar or vector from
// scalars and vectors (arithmetic, comparisons, logic, conversions, GLSL.std.450) as RPU
// instructions. Those one RPU instruction computes are rows of a table; the others are
// small named functions (select.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <spirv/unified1/spirv.hpp11>

#include "cc/builder.hpp"

namespace rpu::cc {

// An instruction's operands as selection reads them; the lowering knows their values.
class Operands {
 public:
  virtual ~Operands() = default;
  // Operand k as a scalar or vector; what makes it (a constant, a load) is made at the
  // first read.
  virtual Src value(std::size_t k) = 0;
  // Operand k's bits if it is a constant scalar or a vector of one constant.
  virtual std::optional<std::uint32_t> constant(std::size_t k) const = 0;
  // The columns of operand k, a matrix.
  virtual std::vector<Src> columns(std::size_t k) = 0;
  // s holds integers in [0, 2^31) only (launch ids and sizes).
  virtual bool below_2_31(const Src& s) const = 0;
};

// The result, of `width` lanes, of SPIR-V op `op`; nullopt if `op` is not one that
// selection knows.
std::optional<Src> select(Builder& b, spv::Op op, int width, Operands& operands);

// The result of GLSL.std.450 instruction `instruction` (operands after the set and the
// instruction number); refuses the ones the back end does not have, naming them.
Src select_glsl_std_450(Builder& b, std::uint32_t instruction, int width, Operands& operands);

}  // namespace rpu::cc
