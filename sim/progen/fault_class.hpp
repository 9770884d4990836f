#pragma once

#include <array>
#include <optional>
#include <string_view>

// The faults a random program can be asked to end in: the rows of docs/shader-core.md
// "Faults", split where one row has several causes (an illegal instruction is an
// unknown opcode, a stray field bit, a register past the count, ...), so that coverage
// shows each cause. The traversal-stack fault is not among them: the kd-tree builder
// never builds a tree deeper than the traversal unit's stack, so no program can cause it.
namespace rpu::progen {

enum class FaultClass : unsigned char {
  kNone,  // every thread halts
  kIllegalOpcode,
  kIllegalUnusedField,
  kIllegalRegister,
  kIllegalSt1Mask,
  kIllegalSpecial,
  kMisaligned,
  kOutOfRangeUnmapped,
  kOutOfRangeSegmentEnd,
  kOutOfRangeReadOnly,
  kOutOfRangeOtherPixel,
  kOutOfRangeStack,
  kStackOverflow,
  kStackUnderflow,
  kCallDepthOverflow,
  kReturnStackEmpty,
  kShaderId,
  kWatchdog,
  kSpin,
  kPc,
};

struct FaultClassInfo {
  FaultClass fault;
  std::string_view name;     // for the command line: "illegal-opcode"
  std::string_view message;  // what the functional model's fault message contains
};

// Every class but kNone, in the order of the enum.
extern const std::array<FaultClassInfo, 19> kFaultClasses;

std::string_view fault_name(FaultClass fault);  // "halt" for kNone
// The class of a name as fault_name gives it; nullopt if there is none.
std::optional<FaultClass> fault_by_name(std::string_view name);
// The class of a functional-model fault message (functional::ShaderFault::what()),
// read from the message alone; nullopt if it matches none.
std::optional<FaultClass> classify_fault_message(std::string_view message);

}  // namespace rpu::progen
