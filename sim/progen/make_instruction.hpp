#pragma once

#include <array>
#include <cstdint>

#include "isa/instruction.hpp"

// Instructions built field by field, for the generator and the renderer.
namespace rpu::progen {

// The loads random programs draw from, in the order coverage counts them.
inline constexpr std::array<isa::Opcode, 4> kLoads{isa::Opcode::kLd, isa::Opcode::kLdf, isa::Opcode::kLd1,
                                                   isa::Opcode::kLd1f};

inline isa::Source reg(int r, std::uint8_t swizzle = isa::kIdentitySwizzle) {
  return {static_cast<std::uint8_t>(r), swizzle, false, false};
}

// The swizzle that repeats one lane: .x = 0x00, .y = 0x55, .z = 0xaa, .w = 0xff.
inline std::uint8_t broadcast(int lane) { return static_cast<std::uint8_t>(0x55 * lane); }

inline isa::Instruction make_instruction(isa::Opcode op, int dst = 0, int wmask = isa::kAllLanes, isa::Source a = {},
                                         isa::Source b = {}, isa::Source c = {}, std::uint32_t imm = 0) {
  isa::Instruction i;
  i.spec = isa::find_insn(op);
  i.dst = static_cast<std::uint8_t>(dst);
  i.wmask = static_cast<std::uint8_t>(wmask);
  i.src = {a, b, c};
  i.imm = imm;
  return i;
}

// The lane-mask bit of lane l.
inline int lane_bit(int lane) { return 1 << lane; }

}  // namespace rpu::progen
