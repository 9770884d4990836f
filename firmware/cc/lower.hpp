// SPIR-V (one optimised shader) to the machine IR.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "cc/frontend.hpp"
#include "cc/mir.hpp"
#include "cc/spirv_module.hpp"

namespace rpu::cc {

// The registers compiled shaders pass values in (docs/shaders.md "Calling convention").
inline constexpr int kRegOrigin = 0;   // (origin, t_min) of the ray
inline constexpr int kRegDirection = 1;  // (direction, t_max)
inline constexpr int kRegHit = 2;      // the hit record (t, u, v, primitive)
inline constexpr int kRegInfo = 3;     // (material index, nesting level of the ray, -, -)
inline constexpr int kRegPayload = 4;  // the payload, one register per member leaf

// One traceRayEXT form: which runtime routine (emit.cpp) a call goes to.
struct TraceForm {
  bool any_hit = false;       // gl_RayFlagsTerminateOnFirstHitEXT: tracea
  bool skip_closest = false;  // gl_RayFlagsSkipClosestHitShaderEXT
  int miss = -1;              // index into the miss shaders, -1: none to call
  auto operator<=>(const TraceForm&) const = default;
  std::string label() const;
};

struct LowerContext {
  int registers = 16;             // what the firmware may use
  int miss_shaders = 0;           // how many .rmiss files the firmware has
};

struct Lowered {
  MFunction function;
  std::set<TraceForm> traces;  // the forms this shader calls
  bool reads_aperture = false;  // reads the camera's lens aperture: the firmware models a thin lens
};

// The code label of a shader: raygen, hit_<stem>, miss_<stem>.
std::string shader_label(const SpirvShader& shader);

// Throws rpu::Error naming the source line and the SPIR-V feature the back end does not support.
Lowered lower(const Module& module, const SpirvShader& shader, const LowerContext& context);

}  // namespace rpu::cc
