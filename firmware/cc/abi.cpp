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
  call.imm = Imm::code_label(form.label());
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
MFunction trace_routine(const TraceForm& form, const std::vector<std::string>& miss_labels) {
  MFunction f;
  f.label = form.label();
  f.name = f.label;
  Builder b(f);
  const int r0 = b.fixed(4, kRegOrigin), r1 = b.fixed(4, kRegDirection), r2 = b.fixed(4, kRegHit);
  const int r3 = b.fixed(4, kRegInfo);
  const int r3x = b.fixed(1, kRegInfo, 0), r3y = b.fixed(1, kRegInfo, 1), r3z = b.fixed(1, kRegInfo, 2);
  const int r3w = b.fixed(1, kRegInfo, 3);
  const Src hit_primitive = component(whole(r2, 4), 3);
  const auto into = [&](int dst, Opcode op, std::vector<Src> srcs, Imm imm = {}) -> MInst& {
    MInst i;
    i.op = op;
    i.dst = dst;
    i.srcs = std::move(srcs);
    i.imm = std::move(imm);
    return b.push(std::move(i));
  };
  const auto scalar = [](int v) { return whole(v, 1); };
  const auto field = [](const spec::isa::AsmSymbol& s) { return Imm::memory_map(s); };
  b.label(f.label);
  into(r3z, Opcode::kLi, {}, field(memory_map_symbol("DEVICE_LAUNCH_BASE")));
  into(r3w, Opcode::kLd1, {scalar(r3z)}, field(memory_map_symbol("LAUNCH_MAX_DEPTH_AT")));
  into(r3w, Opcode::kIaddi, {scalar(r3w)}, Imm::integer(1));
  into(r3w, Opcode::kIlt, {scalar(r3w), scalar(r3y)}).note = "nested deeper than max depth + 1?";
  b.cond_branch(true, scalar(r3w), std::string(kRecursionLimitLabel));
  into(r2, form.any_hit ? Opcode::kTracea : Opcode::kTrace, {whole(r0, 4), whole(r1, 4)});
  into(r3w, Opcode::kIaddi, {hit_primitive}, Imm::integer(1));  // 0 on a miss: primitive 0xffffffff
  const std::string done = form.label() + "_done";
  const std::string miss = form.miss < 0 ? done : miss_labels.at(static_cast<std::size_t>(form.miss));
  b.cond_branch(false, scalar(r3w), miss);
  if (!form.skip_closest) {
    // The hit triangle's material's shader, through the launch block's tables.
    into(r3w, Opcode::kLd1, {scalar(r3z)}, field(memory_map_symbol("LAUNCH_TRIANGLES_AT")));
    into(r3x, Opcode::kImuli, {hit_primitive}, field(memory_map_symbol("TRIANGLE_BYTES")));
    into(r3w, Opcode::kIadd, {scalar(r3w), scalar(r3x)});
    into(r3x, Opcode::kLd1, {scalar(r3w)}, field(memory_map_symbol("TRIANGLE_MATERIAL_AT")));
    into(r3w, Opcode::kLd1, {scalar(r3z)}, field(memory_map_symbol("LAUNCH_MATERIALS_AT")));
    into(r3z, Opcode::kImuli, {scalar(r3x)}, field(memory_map_symbol("MATERIAL_BYTES")));
    into(r3w, Opcode::kIadd, {scalar(r3w), scalar(r3z)});
    into(r3w, Opcode::kLd1, {scalar(r3w)}, field(memory_map_symbol("MATERIAL_SHADER_AT")));
    into(r3z, Opcode::kMfra, {}).note = "kept on the memory stack: the return stack";
    into(-1, Opcode::kPush, {whole(r3, 4)}).note = "stays one entry deep at any nesting";
    into(-1, Opcode::kCalli, {scalar(r3w)});
    into(r3, Opcode::kPop, {});
    into(-1, Opcode::kMtra, {scalar(r3z)});
  }
  if (form.miss < 0) b.label(done);
  MInst ret;
  ret.kind = Kind::kRet;
  b.push(std::move(ret));
  return f;
}

std::vector<MachineItem> recursion_limit() {
  std::vector<MachineItem> code;
  code.emplace_back(Label{std::string(kRecursionLimitLabel),
                          "a trace nested deeper than max depth + 1: stop the thread with an illegal-instruction fault"});
  code.emplace_back(IllegalWord{});
  return code;
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
