// The calling convention of compiled shaders (docs/shaders.md "Calling convention",
// "Recursion"): the registers a shader is entered with and returns in, a trace's call
// of its routine, the trace routines themselves, and the stack the firmware declares.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cc/builder.hpp"
#include "cc/frontend.hpp"
#include "cc/machine.hpp"
#include "rpu/spec.hpp"

namespace rpu::cc {

inline constexpr int kRegOrigin = 0;     // (origin, t_min) of the ray
inline constexpr int kRegDirection = 1;  // (direction, t_max)
inline constexpr int kRegHit = 2;        // the hit record (t, u, v, primitive)
inline constexpr int kRegInfo = 3;       // (material index, nesting level of the ray, -, -)
inline constexpr int kRegPayload = 4;    // the payload, one register per member leaf

// The most registers an instruction names (its register fields) and the lanes of each:
// the bound of --registers and of what the back end keeps in registers.
inline constexpr int kMaxRegisters = 1 << spec::isa::kDstField.width;
inline constexpr int kLanes = spec::isa::kWmaskField.width;

// One traceRayEXT form: which trace routine a call goes to.
struct TraceForm {
  bool any_hit = false;       // gl_RayFlagsTerminateOnFirstHitEXT: tracea
  bool skip_closest = false;  // gl_RayFlagsSkipClosestHitShaderEXT
  int miss = -1;              // index into the miss shaders, -1: none to call
  auto operator<=>(const TraceForm&) const = default;
  std::string label() const;
};

// The code label of a shader, which the shader table names: raygen, hit_<stem>, miss_<stem>.
std::string shader_label(const SpirvShader& shader);

// The payload's registers, r4 on: one fixed vreg per scalar or vector leaf of `widths`
// lanes, in declaration order. Refuses a payload past the last of `registers`.
std::vector<int> payload_registers(Builder& b, const std::vector<int>& widths, int registers);

// What a hit or miss shader is entered with, each part a vreg of its own copied out of
// the ABI's registers (so that a nested trace may reuse them, and a part no longer used
// frees its lanes); -1 where the stage has none.
struct Entry {
  int origin = -1, tmin = -1, direction = -1, tmax = -1;
  int hit_t = -1, barycentrics = -1, primitive = -1;  // closest hit only
  int material = -1, level = -1;                      // the material index, the ray's nesting level
  std::vector<int> payload;                           // the payload's registers (fixed vregs)
};
Entry enter(Builder& b, Stage stage, const std::vector<int>& payload_widths, int registers);

// A shader that traces keeps its return address: the return stack stays one entry deep.
int save_return_address(Builder& b);

// Ray generation halts; a hit or miss shader returns the payload in r4.. (and first puts
// its return address back, if it saved one).
void leave(Builder& b, Stage stage, const std::vector<int>& payload_widths, const std::vector<Src>& payload,
           int return_address, int registers);

// A trace: the ray into r0 and r1, the new ray's nesting level into r3.y (0 from ray
// generation, `level` + 1 elsewhere); then the call of the routine of `form` with the
// payload in r4.. and its copy back.
std::vector<int> set_ray(Builder& b, const Src& origin, const Src& tmin, const Src& direction, const Src& tmax,
                         int level);
void call_trace_routine(Builder& b, const TraceForm& form, std::vector<int> ray, const std::vector<int>& payload_widths,
                        const std::vector<Src>& payload, int registers);

// The routine behind one traceRayEXT form, on machine registers (pinned vregs).
MFunction trace_routine(const TraceForm& form, const std::vector<std::string>& miss_labels);

// Where a trace nested deeper than max depth + 1 goes, after the trace routines: the
// label rpu_trace_recursion_limit on a word that stops the thread with an
// illegal-instruction fault (docs/shaders.md "Recursion").
inline constexpr std::string_view kRecursionLimitLabel = "rpu_trace_recursion_limit";
std::vector<MachineItem> recursion_limit();

// The firmware's declarations of its needs (.equ constants the device checks): one
// return stack entry, and the stack bytes from what ray generation and the hit and miss
// shaders keep on it at once (spills, saves at a trace).
std::vector<Declaration> declarations(int raygen_stack_bytes, int shader_stack_bytes, bool thin_lens);

}  // namespace rpu::cc
