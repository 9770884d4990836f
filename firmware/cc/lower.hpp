// SPIR-V (one optimised shader) to the machine IR.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cc/abi.hpp"
#include "cc/frontend.hpp"
#include "cc/mir.hpp"
#include "cc/spirv_module.hpp"

namespace rpu::cc {

struct LowerContext {
  int registers = 16;             // what the firmware may use
  int miss_shaders = 0;           // how many .rmiss files the firmware has
};

// A ray payload's type: the registers of the calling convention hold its scalar and
// vector leaves in order, so shaders that pass one payload must agree on those.
struct PayloadType {
  std::string leaves;  // e.g. "vec3 uint": what must agree
  std::string glsl;    // how GLSL spells the type, for messages
  std::string where;   // "file" or "file:line": the variable, or the trace
  bool operator==(const PayloadType& o) const { return leaves == o.leaves; }
};

struct Lowered {
  MFunction function;
  std::set<TraceForm> traces;  // the forms this shader calls
  bool reads_aperture = false;  // reads the camera's lens aperture: the firmware models a thin lens
  std::optional<PayloadType> incoming;                       // its rayPayloadInEXT
  std::vector<std::pair<TraceForm, PayloadType>> traced;     // each traceRayEXT's payload
};

// Throws rpu::Error naming the source line and the SPIR-V feature the back end does not support.
Lowered lower(const Module& module, const SpirvShader& shader, const LowerContext& context);

}  // namespace rpu::cc
