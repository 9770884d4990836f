#include "functional/shader_core.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "fp/fast32.hpp"
#include "functional/arith.hpp"

namespace rpu::functional {

namespace si = spec::isa;
namespace mm = spec::memory;
using isa::Instruction;
using Opcode = si::Opcode;
using Vec = std::array<std::uint32_t, 4>;

std::uint64_t ShaderStats::instructions() const {
  std::uint64_t n = 0;
  for (const std::uint64_t r : retired) n += r;
  return n;
}

ShaderStats& ShaderStats::operator+=(const ShaderStats& o) {
  for (std::size_t i = 0; i < retired.size(); ++i) retired[i] += o.retired[i];
  chunk_issues += o.chunk_issues;
  lanes_issued += o.lanes_issued;
  pixels += o.pixels;
  closest_rays += o.closest_rays;
  any_rays += o.any_rays;
  nodes += o.nodes;
  leaves += o.leaves;
  tests += o.tests;
  self_hits += o.self_hits;
  self_hits_counted = self_hits_counted || o.self_hits_counted;
  return *this;
}

namespace {

// Float instructions read their lanes with Arith::load (rounded into the format) and
// write them with Arith::store (widened to fp32), docs/numbers.md: SoftArith for any
// format, Fast32Arith for fp32 on host float (under a FlushScope).

// mov's sign modifiers act on the raw lane as fp32 bits (spec/isa.toml), in any
// format: the same sign operations as the float modifiers, on fp32.
constexpr SoftArith kFp32Bits{fp::kFp32};

constexpr std::uint32_t kTrue = 0xffffffffu;
constexpr std::uint32_t kMissPrim = 0xffffffffu;

// A ray meets the triangle it leaves when it hits the triangle of its thread's latest
// closest hit (the surface shaders spawn shadow, reflected and refracted rays from; a
// ray that leaves a planar triangle cannot meet it again but by rounding) near its
// origin: within 16 ulps of the format at its largest coordinate, or a thousandth of
// that coordinate, whichever is farther (an fp32 offset of the scene's ray_epsilon).
// Near, so that a pixel's next camera ray that meets the same triangle from afar is
// not one.
bool self_hit(const TraceRay& ray, const TraceHit& hit, std::uint32_t last_hit, fp::Format format) {
  if (!hit.hit || hit.prim != last_hit) return false;
  float origin = 0.0f, direction = 0.0f;
  for (int i = 0; i < 3; ++i) {
    origin = std::max(origin, std::fabs(ray.origin[i]));
    direction = std::max(direction, std::fabs(ray.direction[i]));
  }
  if (!std::isfinite(origin)) return false;  // a defined miss; ilogb of 0 is no exponent
  const double ulp = origin > 0.0f ? std::ldexp(1.0, std::ilogb(origin) - format.fraction_bits) : 0.0;
  const double near = std::max(16.0 * ulp, std::ldexp(static_cast<double>(origin), -10));
  return static_cast<double>(hit.t) * static_cast<double>(direction) <= near;
}

Vec swizzle(const Vec& r, std::uint8_t swz) {
  return {r[swz & 3], r[(swz >> 2) & 3], r[(swz >> 4) & 3], r[(swz >> 6) & 3]};
}

}  // namespace

std::uint32_t raygen_entry(const isa::Firmware& firmware) {
  const auto entry = firmware.symbols.find("raygen");
  if (entry == firmware.symbols.end() || entry->second.kind != isa::Symbol::Kind::kCode) {
    throw Error("the firmware has no code label 'raygen' (the ray-generation entry point every thread starts at)");
  }
  return entry->second.value;
}

ShaderCore::ShaderCore(const isa::Firmware& firmware, DeviceMemory& memory, const Tracer& tracer, fp::Format format,
                       const ShaderCoreConfig& config, bool fast_path)
    : firmware_(firmware),
      memory_(memory),
      tracer_(tracer),
      format_(format),
      config_(config),
      fast_(fast_path && format == fp::kFp32),
      raygen_(raygen_entry(firmware)) {
  code_.resize(firmware.code.size());
  uses_.resize(firmware.code.size());
  illegal_why_.resize(firmware.code.size());
  for (std::size_t pc = 0; pc < firmware.code.size(); ++pc) {
    std::string why;
    if (auto insn = isa::decode(firmware.code[pc], &why)) {
      code_[pc] = *insn;
      uses_[pc] = isa::register_use(*insn);
    } else {
      illegal_why_[pc] = why;
    }
  }
}

void ShaderCore::fault(const Thread& t, spec::isa::FaultKind kind, const std::string& what,
                       std::uint32_t address) const {
  const std::string insn =
      t.pc < firmware_.code.size() ? isa::disassemble(firmware_.code[t.pc]) : std::string("past the end of the code");
  // The code label the pc is at or after names the routine (compiled firmware's
  // rpu_trace_recursion_limit, a shader's entry).
  const isa::Symbol* nearest = nullptr;
  std::string_view nearest_name;
  for (const auto& [name, sym] : firmware_.symbols) {
    if (sym.kind == isa::Symbol::Kind::kCode && sym.value <= t.pc && (nearest == nullptr || sym.value > nearest->value)) {
      nearest = &sym;
      nearest_name = name;
    }
  }
  const std::string label = nearest == nullptr       ? std::string()
                            : t.pc == nearest->value ? fmt::format("code label {}", nearest_name)
                                                     : fmt::format("code label {} + {}", nearest_name, t.pc - nearest->value);
  // The source line first: the GLSL or assembly line the instruction was made for.
  const std::optional<std::string> line =
      t.pc < firmware_.code.size() ? firmware_.lines.where(t.pc) : std::optional<std::string>();
  const std::string routine = line         ? fmt::format(" ({}{}{})", *line, label.empty() ? "" : "; ", label)
                              : nearest    ? fmt::format(" ({}{})", t.pc == nearest->value ? "at " : "", label)
                                           : std::string();
  const std::uint32_t width = memory_.launch_block().size() >= 8
                                  ? memory_.load32(mm::kDeviceLaunchBase + mm::kLaunchWidthAt)
                                  : 1;
  const std::uint32_t p = t.lane.pixel;
  throw ShaderFault(fmt::format("shader fault in thread {} (core {}, chunk {}, lane {}; pixel {}, {}) at pc {} "
                                "({}): {}{}",
                                t.lane.thread, t.lane.core, t.lane.chunk, t.lane.lane, p % width, p / width, t.pc,
                                insn, what, routine),
                    p, kind, t.pc, address);
}

std::string ShaderCore::trace_line(const StepRecord& record, const Thread& after) const {
  const std::optional<std::string> line = firmware_.lines.where(record.pc);
  std::string text = fmt::format("{:>6}  {:<28}  {:<36}", record.pc, line.value_or("-"),
                                 record.insn ? isa::disassemble(*record.insn) : isa::disassemble(word(record.pc)));
  const int dst = record.pc < uses_.size() ? uses_[record.pc].dst : -1;
  if (dst < 0 || record.insn == nullptr || static_cast<std::size_t>(dst) >= after.regs.size()) return text;
  std::string floats, bits;
  for (int k = 0; k < 4; ++k) {
    if (!(record.insn->wmask >> k & 1)) continue;
    const std::uint32_t b = after.regs[static_cast<std::size_t>(dst)][static_cast<std::size_t>(k)];
    // Bits with a zero exponent are a subnormal or zero as a float (which the chip
    // flushes), so most likely an integer: shown as one.
    const bool integer = (b & 0x7f800000u) == 0;
    floats += fmt::format("{}{}", floats.empty() ? "" : ", ",
                          integer ? fmt::format("{}", b) : fmt::format("{:g}", std::bit_cast<float>(b)));
    bits += fmt::format("{}{:#010x}", bits.empty() ? "" : " ", b);
  }
  return fmt::format("{}  {} = ({}) [{}]", text, isa::destination_text(static_cast<std::uint8_t>(dst), record.insn->wmask),
                     floats, bits);
}

ShaderCoreConfig ShaderCoreConfig::of(const spec::HardwareConfig& config, std::uint64_t watchdog) {
  ShaderCoreConfig c;
  c.registers = config.registers;
  c.chunk_size = config.chunk_size;
  c.call_depth = config.call_depth;
  c.stack_bytes = static_cast<std::uint32_t>(config.stack_bytes);
  c.watchdog = watchdog;
  return c;
}

std::uint32_t ShaderCore::stack_slot(std::uint32_t thread, std::uint32_t slot) const {
  return mm::kDeviceStackBase + thread * (config_.stack_bytes + mm::kDeviceStackSkew) + config_.stack_bytes - (slot + 1) * 16;
}

void ShaderCore::Chunk::update_next_pc() {
  next_pc_ = kDone;
  for (const Thread& t : threads_) {
    if (!t.done) next_pc_ = std::min(next_pc_, t.pc);
  }
}

void ShaderCore::start(Chunk& chunk, std::span<const Lane> lanes, ShaderStats& stats) const {
  chunk.threads_.resize(lanes.size());
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    Thread& t = chunk.threads_[i];
    t.lane = lanes[i];
    t.pc = raygen_;
    t.done = false;
    t.retired = 0;
    t.spin = 0;
    t.regs.assign(static_cast<std::size_t>(config_.registers), Vec{});
    t.returns.clear();
    t.stack.clear();
    t.last_hit = kMissPrim;
  }
  chunk.fault_.reset();
  chunk.update_next_pc();
  stats.pixels += lanes.size();
}

void ShaderCore::step(Chunk& chunk, ShaderStats& stats, StepRecord* record) {
  if (fast_ && fp::fast32::flush_mode_active()) {
    // A caller stepping many times holds one FlushScope for all of them (the cycle
    // device holds one per frame): setting MXCSR twice a step costs more than the check.
    step_with(Fast32Arith{}, chunk, stats, record);
  } else if (fast_) {
    const fp::fast32::FlushScope flush;
    step_with(Fast32Arith{}, chunk, stats, record);
  } else {
    step_with(SoftArith{format_}, chunk, stats, record);
  }
}

template <class Arith>
void ShaderCore::step_with(const Arith& ar, Chunk& chunk, ShaderStats& stats, StepRecord* record) {
  const std::uint32_t pc = chunk.next_pc_;
  ++stats.chunk_issues;
  stats.lanes_issued += static_cast<std::uint64_t>(config_.chunk_size);
  if (record) {
    record->pc = pc;
    record->insn = instruction(pc);
    record->lanes = 0;
    record->accesses.clear();
    record->trace_count = 0;
  }
  for (std::size_t l = 0; l < chunk.threads_.size(); ++l) {
    Thread& t = chunk.threads_[l];
    if (t.done || t.pc != pc) continue;
    if (record) record->lanes |= 1u << l;
    try {
      execute(ar, t, stats, record);
    } catch (const ShaderFault& f) {
      t.done = true;
      if (!chunk.fault_ || f.pixel() < chunk.fault_->pixel()) chunk.fault_ = f;
      // Later pixels cannot be the one reported; earlier ones run on to halt or fault.
      for (Thread& u : chunk.threads_) {
        if (u.lane.pixel > chunk.fault_->pixel()) u.done = true;
      }
    }
  }
  chunk.update_next_pc();
}

void ShaderCore::run_chunk(std::span<const Lane> lanes, ShaderStats& stats,
                           std::vector<std::vector<Vec>>* end_registers, const StepObserver* observe) {
  Chunk chunk;
  start(chunk, lanes, stats);
  StepRecord record;
  const auto run = [&](const auto& ops) {
    while (!chunk.done()) {
      step_with(ops, chunk, stats, observe ? &record : nullptr);
      if (observe) (*observe)(record, chunk);
    }
  };
  if (fast_) {
    const fp::fast32::FlushScope flush;
    run(Fast32Arith{});
  } else {
    run(SoftArith{format_});
  }
  if (chunk.fault_) throw *chunk.fault_;
  if (end_registers) {
    end_registers->clear();
    for (const Thread& t : chunk.threads_) end_registers->push_back(t.regs);
  }
}

template <class Arith>
void ShaderCore::execute(const Arith& ar, Thread& t, ShaderStats& stats, StepRecord* record) {
  if (t.pc >= code_.size()) fault(t, si::FaultKind::kPc, fmt::format("pc {} is past the end of the code ({} instructions)", t.pc, code_.size()));
  const Instruction& in = code_[t.pc];
  if (!in.spec) fault(t, si::FaultKind::kIllegal, "illegal instruction: " + illegal_why_[t.pc]);
  if (++t.retired > config_.watchdog) {
    fault(t, si::FaultKind::kWatchdog, fmt::format("watchdog: the thread retired {} instructions for one pixel; a runaway shader?",
                         config_.watchdog));
  }
  ++stats.retired[static_cast<std::size_t>(in.spec->cls)];
  const int nregs = config_.registers;
  const auto check_reg = [&](int r, std::string_view role) {
    if (r >= nregs) {
      fault(t, si::FaultKind::kRegister, fmt::format("illegal instruction: {} register r{} does not exist (the configuration has {})", role, r,
                           nregs));
    }
  };
  const isa::RegisterUse& use = uses_[t.pc];
  if (use.dst >= 0) check_reg(use.dst, "destination");
  if (use.data >= 0) check_reg(use.data, "data");
  for (const int r : use.src) {
    if (r >= 0) check_reg(r, "source");
  }
  // With nothing but the pc written, the pcs of more such instructions in a row than the
  // code has must repeat, with the same registers and memory each time: the thread can
  // never end (spec/isa.toml [spin]).
  if (!in.spec->pc_only) {
    t.spin = 0;
  } else if (t.spin++ >= code_.size()) {
    fault(t, si::FaultKind::kSpin,
          fmt::format("spin: the thread loops without writing anything ({} branches in a row that wrote only the "
                      "pc, as many as the code has instructions), so it can never end; a runaway shader",
                      code_.size()));
  }

  // Raw source lanes (swizzled) and float source lanes (rounded into the format, abs,
  // then neg).
  const auto raw = [&](int s) { return swizzle(t.regs[in.src[s].reg], in.src[s].swizzle); };
  using Value = typename Arith::Value;
  using Values = std::array<Value, 4>;
  const auto flt = [&](int s) {
    const Vec v = raw(s);
    Values r;
    for (int i = 0; i < 4; ++i) {
      r[i] = ar.load(v[i]);
      if (in.src[s].abs) r[i] = ar.abs(r[i]);
      if (in.src[s].neg) r[i] = ar.neg(r[i]);
    }
    return r;
  };
  Vec& dst = t.regs[in.dst];
  const auto write = [&](const Vec& v) {
    for (int i = 0; i < 4; ++i) {
      if (in.wmask >> i & 1) dst[i] = v[i];
    }
  };
  const auto write_float = [&](const Values& v) {
    write({ar.store(v[0]), ar.store(v[1]), ar.store(v[2]), ar.store(v[3])});
  };
  const auto float_unary = [&](auto op) {
    Values a = flt(0);
    for (Value& x : a) x = op(x);
    write_float(a);
  };
  const auto float_binary = [&](auto op) {
    const Values a = flt(0), b = flt(1);
    Values r;
    for (int i = 0; i < 4; ++i) r[i] = op(a[i], b[i]);
    write_float(r);
  };
  const auto compare = [&](auto op) {
    const Values a = flt(0), b = flt(1);
    Vec r;
    for (int i = 0; i < 4; ++i) r[i] = op(a[i], b[i]) ? kTrue : 0;
    write(r);
  };
  const auto int_binary = [&](auto op) {
    const Vec a = raw(0), b = raw(1);
    Vec r;
    for (int i = 0; i < 4; ++i) r[i] = op(a[i], b[i]);
    write(r);
  };
  const auto int_imm = [&](auto op) {
    const Vec a = raw(0);
    Vec r;
    for (int i = 0; i < 4; ++i) r[i] = op(a[i], in.imm);
    write(r);
  };
  const auto address = [&](std::uint32_t bytes, bool store) {
    const std::uint32_t addr = raw(0)[0] + in.imm;
    if (record) record->accesses.push_back({addr, bytes, store, t.lane.lane});
    return addr;
  };
  const auto mem_check = [&](std::uint32_t addr, std::uint32_t bytes, bool store) {
    const DeviceMemory::Access a = memory_.check(addr, bytes, store, t.lane.pixel);
    if (!a.ok) fault(t, si::FaultKind::kMemory, a.problem, addr);
  };
  const auto load_vec = [&](bool to_format) {
    const std::uint32_t addr = address(16, false);
    mem_check(addr, 16, false);
    Vec v;
    for (int i = 0; i < 4; ++i) {
      v[i] = memory_.load32(addr + 4 * static_cast<std::uint32_t>(i));
      if (to_format) v[i] = ar.store(ar.load(v[i]));
    }
    write(v);
  };
  const auto load_one = [&](bool to_format) {
    const std::uint32_t addr = address(4, false);
    mem_check(addr, 4, false);
    std::uint32_t v = memory_.load32(addr);
    if (to_format) v = ar.store(ar.load(v));
    write({v, v, v, v});
  };
  const auto push_return = [&](std::uint32_t pc) {
    if (t.returns.size() >= static_cast<std::size_t>(config_.call_depth)) {
      fault(t, si::FaultKind::kCallOverflow, fmt::format("call-depth overflow: the return stack holds {} entries (call_depth of the configuration)",
                           config_.call_depth));
    }
    t.returns.push_back(pc);
  };
  const auto call = [&](std::uint32_t target) {
    push_return(t.pc + 1);
    t.pc = target;
  };
  const std::uint32_t stack_slots = config_.stack_bytes / 16;
  // The address of the thread's top stack slot.
  const auto sp = [&]() {
    return stack_slot(t.lane.thread, static_cast<std::uint32_t>(t.stack.size()) - 1);
  };

  std::uint32_t next = t.pc + 1;
  switch (in.opcode()) {
    case Opcode::kMov:
      if (in.src[0].neg || in.src[0].abs) {
        // Sign modifiers act on the lane as an fp32 value; the raw bits move otherwise.
        Vec v = raw(0);
        for (std::uint32_t& x : v) {
          if (in.src[0].abs) x = kFp32Bits.abs(x);
          if (in.src[0].neg) x = kFp32Bits.neg(x);
        }
        write(v);
      } else {
        write(raw(0));
      }
      break;
    case Opcode::kAdd: float_binary([&](auto a, auto b) { return ar.add(a, b); }); break;
    case Opcode::kMul: float_binary([&](auto a, auto b) { return ar.mul(a, b); }); break;
    case Opcode::kMad: {
      const Values a = flt(0), b = flt(1), c = flt(2);
      Values r;
      for (int i = 0; i < 4; ++i) r[i] = ar.fma(a[i], b[i], c[i]);
      write_float(r);
      break;
    }
    case Opcode::kDp3:
    case Opcode::kDp4: {
      const Values a = flt(0), b = flt(1);
      Value s = ar.add(ar.mul(a[0], b[0]), ar.mul(a[1], b[1]));
      s = in.opcode() == Opcode::kDp3 ? ar.add(s, ar.mul(a[2], b[2]))
                                      : ar.add(s, ar.add(ar.mul(a[2], b[2]), ar.mul(a[3], b[3])));
      write_float({s, s, s, s});
      break;
    }
    case Opcode::kMin: float_binary([&](auto a, auto b) { return ar.min(a, b); }); break;
    case Opcode::kMax: float_binary([&](auto a, auto b) { return ar.max(a, b); }); break;
    case Opcode::kRcp: float_unary([&](auto a) { return ar.rcp(a); }); break;
    case Opcode::kRsq: float_unary([&](auto a) { return ar.rsqrt(a); }); break;
    case Opcode::kSqrt: float_unary([&](auto a) { return ar.sqrt(a); }); break;
    case Opcode::kFrc: float_unary([&](auto a) { return ar.fract(a); }); break;
    case Opcode::kFlr: float_unary([&](auto a) { return ar.floor(a); }); break;
    case Opcode::kFeq: compare([&](auto a, auto b) { return ar.eq(a, b); }); break;
    case Opcode::kFne: compare([&](auto a, auto b) { return ar.ne(a, b); }); break;
    case Opcode::kFlt: compare([&](auto a, auto b) { return ar.lt(a, b); }); break;
    case Opcode::kFle: compare([&](auto a, auto b) { return ar.le(a, b); }); break;
    case Opcode::kSel: {
      const Vec a = raw(0), b = raw(1), c = raw(2);
      write({a[0] ? b[0] : c[0], a[1] ? b[1] : c[1], a[2] ? b[2] : c[2], a[3] ? b[3] : c[3]});
      break;
    }
    case Opcode::kI2f: {
      const Vec a = raw(0);
      Values r;
      for (int i = 0; i < 4; ++i) r[i] = ar.from_int(static_cast<std::int32_t>(a[i]));
      write_float(r);
      break;
    }
    case Opcode::kF2i: {
      const Values a = flt(0);
      Vec r;
      for (int i = 0; i < 4; ++i) r[i] = static_cast<std::uint32_t>(ar.to_int(a[i]));
      write(r);
      break;
    }
    case Opcode::kIadd: int_binary([](std::uint32_t a, std::uint32_t b) { return a + b; }); break;
    case Opcode::kIsub: int_binary([](std::uint32_t a, std::uint32_t b) { return a - b; }); break;
    case Opcode::kImul: int_binary([](std::uint32_t a, std::uint32_t b) { return a * b; }); break;
    case Opcode::kImulhu:
      int_binary([](std::uint32_t a, std::uint32_t b) {
        return static_cast<std::uint32_t>((std::uint64_t{a} * b) >> 32);
      });
      break;
    case Opcode::kAnd: int_binary([](std::uint32_t a, std::uint32_t b) { return a & b; }); break;
    case Opcode::kOr: int_binary([](std::uint32_t a, std::uint32_t b) { return a | b; }); break;
    case Opcode::kXor: int_binary([](std::uint32_t a, std::uint32_t b) { return a ^ b; }); break;
    case Opcode::kShl: int_binary([](std::uint32_t a, std::uint32_t b) { return a << (b & 31); }); break;
    case Opcode::kShr: int_binary([](std::uint32_t a, std::uint32_t b) { return a >> (b & 31); }); break;
    case Opcode::kSra:
      int_binary([](std::uint32_t a, std::uint32_t b) {
        return static_cast<std::uint32_t>(static_cast<std::int32_t>(a) >> (b & 31));
      });
      break;
    case Opcode::kIeq: int_binary([](std::uint32_t a, std::uint32_t b) { return a == b ? kTrue : 0u; }); break;
    case Opcode::kIlt:
      int_binary([](std::uint32_t a, std::uint32_t b) {
        return static_cast<std::int32_t>(a) < static_cast<std::int32_t>(b) ? kTrue : 0u;
      });
      break;
    case Opcode::kIltu: int_binary([](std::uint32_t a, std::uint32_t b) { return a < b ? kTrue : 0u; }); break;
    case Opcode::kIaddi: int_imm([](std::uint32_t a, std::uint32_t b) { return a + b; }); break;
    case Opcode::kImuli: int_imm([](std::uint32_t a, std::uint32_t b) { return a * b; }); break;
    case Opcode::kAndi: int_imm([](std::uint32_t a, std::uint32_t b) { return a & b; }); break;
    case Opcode::kOri: int_imm([](std::uint32_t a, std::uint32_t b) { return a | b; }); break;
    case Opcode::kXori: int_imm([](std::uint32_t a, std::uint32_t b) { return a ^ b; }); break;
    case Opcode::kShli: int_imm([](std::uint32_t a, std::uint32_t b) { return a << (b & 31); }); break;
    case Opcode::kShri: int_imm([](std::uint32_t a, std::uint32_t b) { return a >> (b & 31); }); break;
    case Opcode::kSrai:
      int_imm([](std::uint32_t a, std::uint32_t b) {
        return static_cast<std::uint32_t>(static_cast<std::int32_t>(a) >> (b & 31));
      });
      break;
    case Opcode::kIlti:
      int_imm([](std::uint32_t a, std::uint32_t b) {
        return static_cast<std::int32_t>(a) < static_cast<std::int32_t>(b) ? kTrue : 0u;
      });
      break;
    case Opcode::kLi: write({in.imm, in.imm, in.imm, in.imm}); break;
    case Opcode::kLif: {
      const std::uint32_t v = ar.store(ar.load(in.imm));
      write({v, v, v, v});
      break;
    }
    case Opcode::kLd: load_vec(false); break;
    case Opcode::kLdf: load_vec(true); break;
    case Opcode::kLd1: load_one(false); break;
    case Opcode::kLd1f: load_one(true); break;
    case Opcode::kSt: {
      const std::uint32_t addr = address(16, true);
      const Vec& v = t.regs[in.dst];
      for (std::uint32_t i = 0; i < 4; ++i) {
        if (in.wmask >> i & 1) mem_check(addr + 4 * i, 4, true);
      }
      for (std::uint32_t i = 0; i < 4; ++i) {
        if (in.wmask >> i & 1) memory_.store32(addr + 4 * i, v[i]);
      }
      break;
    }
    case Opcode::kSt1: {
      if (in.wmask != 1) fault(t, si::FaultKind::kIllegal, "illegal instruction: st1 stores lane x only (write mask .x)");
      const std::uint32_t addr = address(4, true);
      mem_check(addr, 4, true);
      memory_.store32(addr, t.regs[in.dst][0]);
      break;
    }
    case Opcode::kPush:
      if (t.stack.size() >= stack_slots) {
        fault(t, si::FaultKind::kStackOverflow,
              fmt::format("stack overflow: push below the thread's stack ({} bytes at {:#010x}; sp {:#010x})",
                          config_.stack_bytes, stack_slot(t.lane.thread, stack_slots - 1), sp() - 16));
      }
      t.stack.push_back(raw(0));
      if (record) record->accesses.push_back({sp(), 16, true, t.lane.lane});
      break;
    case Opcode::kPop:
      if (t.stack.empty()) {
        fault(t, si::FaultKind::kStackUnderflow,
              fmt::format("stack underflow: pop with nothing pushed (sp {:#010x})", sp()));
      }
      if (record) record->accesses.push_back({sp(), 16, false, t.lane.lane});
      write(t.stack.back());
      t.stack.pop_back();
      break;
    case Opcode::kBra: next = in.imm; break;
    case Opcode::kBz:
      if (raw(0)[0] == 0) next = in.imm;
      break;
    case Opcode::kBnz:
      if (raw(0)[0] != 0) next = in.imm;
      break;
    case Opcode::kCall:
      call(in.imm);
      next = t.pc;
      break;
    case Opcode::kCalli: {
      const std::uint32_t id = raw(0)[0];
      const std::uint32_t count = memory_.load32(mm::kDeviceLaunchBase + mm::kLaunchShaderCountAt);
      if (id >= count) fault(t, si::FaultKind::kShaderId, fmt::format("calli: shader id {} is outside the shader table ({} shaders)", id, count), id);
      const std::uint32_t entry = memory_.load32(mm::kDeviceLaunchBase + mm::kLaunchShaderTableAt) + 4 * id;
      mem_check(entry, 4, false);
      if (record) record->accesses.push_back({entry, 4, false, t.lane.lane});
      call(memory_.load32(entry));
      next = t.pc;
      break;
    }
    case Opcode::kRet:
      if (t.returns.empty()) fault(t, si::FaultKind::kCallUnderflow, "ret with an empty return stack (raygen ends with halt)");
      next = t.returns.back();
      t.returns.pop_back();
      break;
    case Opcode::kMfra: {
      if (t.returns.empty()) fault(t, si::FaultKind::kCallUnderflow, "mfra with an empty return stack");
      const std::uint32_t ra = t.returns.back();
      t.returns.pop_back();
      write({ra, ra, ra, ra});
      break;
    }
    case Opcode::kMtra: push_return(raw(0)[0]); break;
    case Opcode::kHalt: t.done = true; break;
    case Opcode::kTrace:
    case Opcode::kTracea: {
      const Vec a = raw(0), b = raw(1);
      TraceRay ray;
      for (int i = 0; i < 3; ++i) {
        ray.origin[i] = std::bit_cast<float>(a[i]);
        ray.direction[i] = std::bit_cast<float>(b[i]);
      }
      ray.t_min = std::bit_cast<float>(a[3]);
      ray.t_max = std::bit_cast<float>(b[3]);
      const bool any = in.opcode() == Opcode::kTracea;
      const TraceMode mode = any ? TraceMode::kAny : TraceMode::kClosest;
      TraceHit hit;
      try {
        if (record) {
          if (record->trace_count == record->traces.size()) record->traces.emplace_back();
          hit = tracer_.trace(ray, mode, record->traces[record->trace_count++]);
        } else {
          hit = tracer_.trace(ray, mode);
        }
      } catch (const Error& e) {
        fault(t, si::FaultKind::kTraversal, e.what());
      }
      ++(any ? stats.any_rays : stats.closest_rays);
      stats.self_hits += self_hit(ray, hit, t.last_hit, format_) ? 1 : 0;
      stats.self_hits_counted = true;
      if (!any) t.last_hit = hit.hit ? hit.prim : kMissPrim;
      stats.nodes += hit.counters.nodes;
      stats.leaves += hit.counters.leaves;
      stats.tests += hit.counters.tests;
      if (hit.hit) {
        write({std::bit_cast<std::uint32_t>(hit.t), std::bit_cast<std::uint32_t>(hit.u),
               std::bit_cast<std::uint32_t>(hit.v), hit.prim});
      } else {
        write({std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity()), 0, 0, kMissPrim});
      }
      break;
    }
    case Opcode::kRdsr: {
      const Lane& l = t.lane;
      const auto launch = [&](std::uint32_t at) { return memory_.load32(mm::kDeviceLaunchBase + at); };
      const std::uint32_t width = launch(mm::kLaunchWidthAt);
      switch (in.imm) {
        case si::kSpecialPixel: write({l.pixel % width, l.pixel / width, l.pixel, 0}); break;
        case si::kSpecialLaunch: write({width, launch(mm::kLaunchHeightAt), launch(mm::kLaunchSppAt), launch(mm::kLaunchMaxDepthAt)}); break;
        case si::kSpecialThread: write({l.thread, l.core, l.chunk, l.lane}); break;
        case si::kSpecialParams: write({mm::kDeviceLaunchBase, static_cast<std::uint32_t>(memory_.launch_block().size()), 0, 0}); break;
        default: fault(t, si::FaultKind::kIllegal, fmt::format("illegal instruction: no special register {}", in.imm));
      }
      break;
    }
  }
  t.pc = next;
}

}  // namespace rpu::functional
