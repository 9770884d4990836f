#include "cc/abi.hpp"

#include <array>
#include <utility>

#include <fmt/format.h>

namespace rpu::cc {

std::string TraceForm::label() const {
  return fmt::format("rpu_trace_{}{}{}", any_hit ? "any" : "closest", skip_closest ? "_skip" : "",
                     miss < 0 ? std::string("_nomiss") : fmt::format("_miss{}", miss));
}

std::string shader_label(const SpirvShader& shader) {
  const std::string stem = shader.file.stem().string();
  switch (shader.stage) {
    case Stage::kRaygen: return "raygen";
    case Stage::kClosestHit: return "hit_" + stem;
    case Stage::kMiss: return "miss_" + stem;
    case Stage::kAnyHit: return "anyhit_" + stem;
  }
  return stem;
}

std::vector<int> payload_registers(Builder& b, const std::vector<int>& widths, int registers) {
  std::vector<int> regs;
  for (const int n : widths) {
    const int reg = kRegPayload + static_cast<int>(regs.size());
    if (reg >= registers) {
      b.unsupported(fmt::format("a ray payload of more than {} scalar or vector members (one register each)",
                                registers - kRegPayload));
    }
    regs.push_back(b.fixed(n, reg));
  }
  return regs;
}

Entry enter(Builder& b, Stage stage, const std::vector<int>& payload_widths, int registers) {
  const bool hit = stage == Stage::kClosestHit;
  MInst e;
  e.kind = Kind::kEntry;
  const int origin = b.fixed(4, kRegOrigin);
  const int direction = b.fixed(4, kRegDirection);
  e.defs = {origin, direction};
  const int hit_record = hit ? b.fixed(4, kRegHit) : -1;
  if (hit) e.defs.push_back(hit_record);
  const int info = b.fixed(4, kRegInfo);
  e.defs.push_back(info);
  Entry entry;
  entry.payload = payload_registers(b, payload_widths, registers);
  e.defs.insert(e.defs.end(), entry.payload.begin(), entry.payload.end());
  b.push(std::move(e));
  // The allocator gives a copy its source's place where it can, and the mov disappears.
  const auto part = [&](int reg, std::array<std::uint8_t, 4> comps, int n) {
    Src s = whole(reg, 4);
    s.comp = comps;
    s.n = n;
    return b.op(Opcode::kMov, n, {s}).v;
  };
  entry.origin = part(origin, {0, 1, 2, 0}, 3);
  entry.tmin = part(origin, {3, 0, 0, 0}, 1);
  entry.direction = part(direction, {0, 1, 2, 0}, 3);
  entry.tmax = part(direction, {3, 0, 0, 0}, 1);
  if (hit) {
    entry.hit_t = part(hit_record, {0, 0, 0, 0}, 1);
    entry.barycentrics = part(hit_record, {1, 2, 0, 0}, 2);
    entry.primitive = part(hit_record, {3, 0, 0, 0}, 1);
  }
  entry.material = part(info, {0, 0, 0, 0}, 1);
  entry.level = part(info, {1, 0, 0, 0}, 1);
  return entry;
}

int save_return_address(Builder& b) { return b.op(Opcode::kMfra, 1, {}).v; }

void leave(Builder& b, Stage stage, const std::vector<int>& payload_widths, const std::vector<Src>& payload,
           int return_address, int registers) {
  if (stage == Stage::kRaygen) {
    MInst h;
    h.kind = Kind::kHalt;
    b.push(std::move(h));
    return;
  }
  MInst r;
  r.kind = Kind::kRet;
  r.uses = payload_registers(b, payload_widths, registers);
  for (std::size_t k = 0; k < r.uses.size(); ++k) b.copy_into(r.uses[k], payload[k]);
  if (return_address >= 0) {
    MInst t;
    t.op = Opcode::kMtra;
    t.srcs = {whole(return_address, 1)};
    b.push(std::move(t));
  }
  b.push(std::move(r));
}

std::vector<int> set_ray(Builder& b, const Src& origin, const Src& tmin, const Src& direction, const Src& tmax,
                         int level) {
  const int o = b.fixed(4, kRegOrigin), d = b.fixed(4, kRegDirection), info = b.fixed(4, kRegInfo);
  b.op_into(o, 0b0111, Opcode::kMov, {origin}, {}, true);
  b.op_into(o, 0b1000, Opcode::kMov, {tmin});
  b.op_into(d, 0b0111, Opcode::kMov, {direction}, {}, true);
  b.op_into(d, 0b1000, Opcode::kMov, {tmax});
  if (level >= 0) {
    b.op_into(info, 0b0010, Opcode::kIaddi, {whole(level, 1)}, Imm::integer(1), true);
  } else {
    b.op_into(info, 0b0010, Opcode::kLi, {}, Imm::integer(0), true);
  }
  return {o, d, info};
}

void call_trace_routine(Builder& b, const TraceForm& form, std::vector<int> ray, const std::vector<int>& payload_widths,
                        const std::vector<Src>& payload, int registers) {
  MInst call;
  call.kind = Kind::kCall;
  call.target = form.label();
  call.uses = std::move(ray);
  const std::vector<int> in = payload_registers(b, payload_widths, registers);
  call.uses.insert(call.uses.end(), in.begin(), in.end());
  for (std::size_t k = 0; k < in.size(); ++k) b.copy_into(in[k], payload[k]);
  const std::vector<int> out = payload_registers(b, payload_widths, registers);
  call.defs = out;
  b.push(std::move(call));
  for (std::size_t k = 0; k < out.size(); ++k) b.copy_into(payload[k].v, b.whole(out[k]));
}

// Entered with r0 = (origin, t_min), r1 = (direction, t_max), r3.y = the new ray's
// nesting level and the payload in r4..; r2 and r3 are scratch. A hit calls the
// material's closest-hit shader through the shader table with r2 = (t, u, v, primitive)
// and r3.x = the material index; a miss jumps to the miss shader, which returns to the
// tracing shader itself.
std::string trace_routine(const TraceForm& form, const std::vector<std::string>& miss_labels) {
  std::string s = fmt::format("{}:\n", form.label());
  s += "        li      r3.z, DEVICE_LAUNCH_BASE\n"
       "        ld1     r3.w, [r3.z + LAUNCH_MAX_DEPTH_AT]\n"
       "        iaddi   r3.w, r3.w, 1\n"
       "        ilt     r3.w, r3.w, r3.y            ; nested deeper than max depth + 1?\n"
       "        bnz     r3.w, rpu_trace_recursion_limit\n";
  s += fmt::format("        {:<7} r2, r0, r1\n", form.any_hit ? "tracea" : "trace");
  s += "        iaddi   r3.w, r2.w, 1\n";
  const std::string miss = form.miss < 0 ? std::string() : miss_labels.at(static_cast<std::size_t>(form.miss));
  s += fmt::format("        bz      r3.w, {}\n", miss.empty() ? form.label() + "_done" : miss);
  if (!form.skip_closest) {
    s += "        ld1     r3.w, [r3.z + LAUNCH_TRIANGLES_AT]\n"
         "        imuli   r3.x, r2.w, TRIANGLE_BYTES\n"
         "        iadd    r3.w, r3.w, r3.x\n"
         "        ld1     r3.x, [r3.w + TRIANGLE_MATERIAL_AT]\n"
         "        ld1     r3.w, [r3.z + LAUNCH_MATERIALS_AT]\n"
         "        imuli   r3.z, r3.x, MATERIAL_BYTES\n"
         "        iadd    r3.w, r3.w, r3.z\n"
         "        ld1     r3.w, [r3.w + MATERIAL_SHADER_AT]\n"
         "        mfra    r3.z                        ; kept on the memory stack: the return stack\n"
         "        push    r3                          ; stays one entry deep at any nesting\n"
         "        calli   r3.w\n"
         "        pop     r3\n"
         "        mtra    r3.z\n";
  }
  if (miss.empty()) s += form.label() + "_done:\n";
  s += "        ret\n";
  return s;
}

std::vector<Declaration> declarations(int raygen_stack_bytes, int shader_stack_bytes, bool thin_lens) {
  // Per nesting level a trace routine's frame (r3, 16 bytes) and what a hit or miss
  // shader keeps; levels run to max depth + 1 (docs/shaders.md "Recursion").
  const int per_level = 16 + shader_stack_bytes;
  std::vector<Declaration> out{
      {"FIRMWARE_RETURN_STACK_ENTRIES", 1, {}},
      {"FIRMWARE_STACK_BYTES", static_cast<std::uint32_t>(raygen_stack_bytes + 2 * per_level), {}},
      {"FIRMWARE_STACK_BYTES_PER_DEPTH", static_cast<std::uint32_t>(per_level), {}},
  };
  if (thin_lens) {
    out.push_back({"FIRMWARE_THIN_LENS", 1, "a shader reads the camera's aperture: the firmware models the thin lens"});
  }
  return out;
}

}  // namespace rpu::cc
