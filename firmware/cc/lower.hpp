// SPIR-V (one optimised shader) to the machine IR.
#pragma once

#include <set>
#include <string>
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

struct Lowered {
  MFunction function;
  std::set<TraceForm> traces;  // the forms this shader calls
  bool reads_aperture = false;  // reads the camera's lens aperture: the firmware models a thin lens
};

// Throws rpu::Error naming the source line and the SPIR-V feature the back end does not support.
Lowered lower(const Module& module, const SpirvShader& shader, const LowerContext& context);

}  // namespace rpu::cc
