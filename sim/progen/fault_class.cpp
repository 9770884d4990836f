#include "progen/fault_class.hpp"

namespace rpu::progen {

// The message fragments are those of cmodel/functional/shader_core.cpp and
// device_memory.cpp; classify_fault_message reads them in this order, so a more
// specific fragment comes before one it contains.
const std::array<FaultClassInfo, 19> kFaultClasses{{
    {FaultClass::kIllegalOpcode, "illegal-opcode", "illegal instruction: unknown opcode"},
    {FaultClass::kIllegalUnusedField, "illegal-unused-field", "that it does not use"},
    {FaultClass::kIllegalRegister, "illegal-register", "does not exist (the configuration has"},
    {FaultClass::kIllegalSt1Mask, "illegal-st1-mask", "illegal instruction: st1 stores lane x only"},
    {FaultClass::kIllegalSpecial, "illegal-special", "illegal instruction: no special register"},
    {FaultClass::kMisaligned, "misaligned", "misaligned access at address"},
    {FaultClass::kOutOfRangeUnmapped, "out-of-range-unmapped", "is outside the device memory"},
    {FaultClass::kOutOfRangeSegmentEnd, "out-of-range-segment-end", "runs past the end of the"},
    {FaultClass::kOutOfRangeReadOnly, "out-of-range-read-only", "in the read-only"},
    {FaultClass::kOutOfRangeOtherPixel, "out-of-range-other-pixel", "outside the thread's own pixel"},
    {FaultClass::kOutOfRangeStack, "out-of-range-stack", "is in the stack segment"},
    {FaultClass::kStackOverflow, "stack-overflow", "stack overflow: push below the thread's stack"},
    {FaultClass::kStackUnderflow, "stack-underflow", "stack underflow: pop with nothing pushed"},
    {FaultClass::kCallDepthOverflow, "call-depth-overflow", "call-depth overflow"},
    {FaultClass::kReturnStackEmpty, "return-stack-empty", "with an empty return stack"},
    {FaultClass::kShaderId, "shader-id", "is outside the shader table"},
    {FaultClass::kWatchdog, "watchdog", "watchdog: the thread retired"},
    {FaultClass::kSpin, "spin", "spin: the thread loops without writing anything"},
    {FaultClass::kPc, "pc", "is past the end of the code"},
}};

std::string_view fault_name(FaultClass fault) {
  for (const FaultClassInfo& f : kFaultClasses) {
    if (f.fault == fault) return f.name;
  }
  return "halt";
}

std::optional<FaultClass> fault_by_name(std::string_view name) {
  if (name == "halt") return FaultClass::kNone;
  for (const FaultClassInfo& f : kFaultClasses) {
    if (f.name == name) return f.fault;
  }
  return std::nullopt;
}

std::optional<FaultClass> classify_fault_message(std::string_view message) {
  for (const FaultClassInfo& f : kFaultClasses) {
    if (message.find(f.message) != std::string_view::npos) return f.fault;
  }
  return std::nullopt;
}

}  // namespace rpu::progen
