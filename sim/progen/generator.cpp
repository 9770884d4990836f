// generate(): random programs that are legal and terminate by construction
// (docs/random-programs.md "What a program holds").
#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "common/error.hpp"
#include "progen/make_instruction.hpp"
#include "progen/progen.hpp"
#include "progen/random.hpp"

namespace rpu::progen {

namespace {

namespace si = spec::isa;
namespace mm = spec::memory;
using isa::Instruction;
using isa::Opcode;
using isa::Operand;

// The memory image's header and section table (one entry per section id, all present:
// docs/memory-map.md): every image has these bytes.
constexpr std::uint32_t kImageHeaderBytes = mm::kHeaderBytes + mm::kSectionEntryBytes * mm::kSectionIdVertexPositions;


std::uint32_t load_bytes(Opcode op) { return op == Opcode::kLd || op == Opcode::kLdf ? 16 : 4; }

// Records the launch block points at, and how many bytes at the pointer every image
// has: a section the scene lacks has address 0, the image's header, which is longer.
struct RecordPointer {
  std::uint32_t at;
  std::uint32_t bytes;
  std::string_view name;
};
constexpr std::array<RecordPointer, 6> kRecordPointers{{
    {mm::kLaunchSceneAt, mm::kSceneRecordBytes, "scene record"},
    {mm::kLaunchMaterialsAt, mm::kMaterialBytes, "first material"},
    {mm::kLaunchTrianglesAt, mm::kTriangleBytes, "first triangle"},
    {mm::kLaunchPositionsAt, mm::kVertexPositionBytes, "first vertex position"},
    {mm::kLaunchLightsAt, mm::kLightBytes, "first light (or the header)"},
    {mm::kLaunchNormalsAt, mm::kVertexNormalBytes, "first vertex normal (or the header)"},
}};

// fp32 bit patterns at the corners of every number format: zeros, subnormals (flushed),
// infinities, NaNs with payloads, the largest and smallest normals, exact small values.
std::uint32_t interesting_float(Random& rng) {
  const std::uint32_t sign = rng.chance(50) ? 0x80000000u : 0u;
  const auto exponent = [&](int lo, int hi) { return static_cast<std::uint32_t>(rng.range(lo, hi)) << 23; };
  static constexpr std::array<std::uint32_t, 8> kExact{0x3f800000u, 0x40000000u, 0x3f000000u, 0x40400000u,
                                                      0x3e800000u, 0x41200000u, 0x4b800000u, 0x4b7fffffu};
  switch (rng.below(12)) {
    case 0: return sign;
    case 1: return sign | (1 + rng.below(0x7fffff));                   // subnormal
    case 2: return sign | 0x7f800000u;                                 // infinity
    case 3: return 0x7fc00000u;                                        // the canonical NaN
    case 4: return sign | 0x7f800000u | (1 + rng.below(0x7fffff));     // quiet or signalling NaN
    case 5: return sign | exponent(0xf0, 0xfe) | rng.below(0x800000);  // huge
    case 6: return sign | exponent(0x01, 0x10) | rng.below(0x800000);  // tiny normal
    case 7: return sign | rng.pick(std::span<const std::uint32_t>(kExact));
    default: return sign | exponent(0x70, 0x8e) | rng.below(0x800000);  // 2^-15 .. 2^16
  }
}

std::uint32_t interesting_int(Random& rng) {
  static constexpr std::array<std::uint32_t, 6> kEdges{0x7fffffffu, 0x80000000u, 0xffffffffu,
                                                       0x80000001u, 0xfffffffeu, 0x00010000u};
  switch (rng.below(8)) {
    case 0: return rng.below(40);  // shift counts, in range and past 31
    case 1: return static_cast<std::uint32_t>(rng.range(-16, 16));
    case 2: return rng.pick(std::span<const std::uint32_t>(kEdges));
    case 3: return 1u << rng.below(32);
    case 4: return interesting_float(rng);
    default: return rng.u32();
  }
}

class Generator {
 public:
  Generator(std::uint64_t seed, const Options& options) : rng_(seed), o_(options) {
    p_.seed = seed;
    p_.machine = options.machine;
    p_.regs = RegisterPlan::for_registers(options.machine.registers);
    p_.fault = options.fault;
    for (const si::InsnSpec& s : si::kInsns) {
      if (is_pure_compute(s)) compute_.push_back(&s);
    }
  }

  Program run() {
    check_options();
    const int words = std::max(o_.data_words, 16);
    for (int i = 0; i < words; ++i) {
      p_.data.push_back(rng_.chance(70) ? interesting_float(rng_) : interesting_int(rng_));
    }
    make_routines();

    std::uint64_t budget = o_.max_instructions;
    if (o_.fault == FaultClass::kWatchdog) {
      p_.watchdog_limit = o_.watchdog;
      budget = std::min(budget, o_.watchdog / 2);
    }
    const Scope top{-1, false, 0,
                    {budget, o_.machine.stack_bytes / 16, static_cast<std::uint32_t>(o_.machine.call_depth)}};
    p_.raygen = block(top, rng_.range(o_.max_statements, 3 * o_.max_statements));
    if (o_.fault != FaultClass::kNone) {
      const auto at = static_cast<std::ptrdiff_t>(rng_.below(static_cast<std::uint32_t>(p_.raygen.size() + 1)));
      p_.raygen.insert(p_.raygen.begin() + at, fault_statement());
    }
    return std::move(p_);
  }

 private:
  // Where a statement is made: which routine (-1: raygen), whether the routine's return
  // address is on top of the return stack (kReturnAddress may move it), how deeply
  // regions nest here, and what the statements here may still cost.
  struct Scope {
    int routine;
    bool return_address;
    int depth;
    Cost room;
  };

  void check_options() const {
    const Machine& m = o_.machine;
    if (m.registers < 8 || m.registers > 64) {
      throw Error(fmt::format("random programs need 8 to 64 registers; the machine has {}", m.registers));
    }
    if (m.call_depth < 1 || m.stack_bytes < 64) {
      throw Error(fmt::format("random programs need a call depth of at least 1 and 64 stack bytes; the machine has "
                              "{} and {}",
                              m.call_depth, m.stack_bytes));
    }
    if (o_.max_statements < 1 || o_.max_routines < 0 || o_.max_nesting < 0) {
      throw Error(fmt::format("random programs need max_statements >= 1, max_routines >= 0 and max_nesting >= 0, "
                              "not {}, {} and {}",
                              o_.max_statements, o_.max_routines, o_.max_nesting));
    }
    if (o_.fault == FaultClass::kIllegalRegister && m.registers == 64) {
      throw Error("no register past the count exists with 64 registers (the encoding's 6-bit fields name r0..r63): "
                  "ask for another fault class");
    }
    if (o_.fault == FaultClass::kWatchdog && o_.watchdog < 64) {
      throw Error(fmt::format("a watchdog-fault program needs a watchdog of at least 64 instructions, not {}",
                              o_.watchdog));
    }
  }

  // ---- registers and operands ----

  int free_reg() { return static_cast<int>(rng_.below(static_cast<std::uint32_t>(p_.regs.free))); }
  int source_reg() {
    if (rng_.chance(80)) return free_reg();
    const std::array<int, 3> kept{p_.regs.pixel, p_.regs.bases, p_.regs.counter};
    return rng_.pick(std::span<const int>(kept));
  }
  std::uint8_t swizzle() {
    switch (rng_.below(10)) {
      case 0:
      case 1:
      case 2:
      case 3: return isa::kIdentitySwizzle;
      case 4:
      case 5: return broadcast(static_cast<int>(rng_.below(4)));
      case 6:
      case 7: {
        std::array<int, 4> lanes{0, 1, 2, 3};
        for (std::uint32_t i = 3; i > 0; --i) std::swap(lanes[i], lanes[rng_.below(i + 1)]);
        return static_cast<std::uint8_t>(lanes[0] | lanes[1] << 2 | lanes[2] << 4 | lanes[3] << 6);
      }
      default: return static_cast<std::uint8_t>(rng_.below(256));
    }
  }
  // A swizzle whose lane x reads `lane`: what a branch, calli, mtra or memory operand uses.
  std::uint8_t swizzle_reading(int lane) { return static_cast<std::uint8_t>((swizzle() & 0xfc) | lane); }
  int write_mask() {
    const std::uint32_t r = rng_.below(20);
    if (r < 10) return isa::kAllLanes;
    if (r == 10) return 0;
    return static_cast<int>(1 + rng_.below(14));
  }
  isa::Source source(bool float_modifiers, bool abs_allowed) {
    isa::Source s = reg(source_reg(), swizzle());
    if (float_modifiers) {
      s.neg = rng_.chance(30);
      s.abs = abs_allowed && rng_.chance(30);
    }
    return s;
  }
  isa::Source base(int lane) { return reg(p_.regs.bases, swizzle_reading(lane)); }
  isa::Source pixel_lane(int lane) { return reg(p_.regs.pixel, broadcast(lane)); }

  Instruction compute(const si::InsnSpec& spec) {
    Instruction i;
    i.spec = &spec;
    for (int k = 0; k < spec.operand_count; ++k) {
      switch (spec.operands[static_cast<std::size_t>(k)]) {
        case Operand::kD:
          i.dst = static_cast<std::uint8_t>(free_reg());
          i.wmask = static_cast<std::uint8_t>(write_mask());
          break;
        case Operand::kA: i.src[0] = source(spec.float_modifiers, true); break;
        case Operand::kB: i.src[1] = source(spec.float_modifiers, true); break;
        case Operand::kC: i.src[2] = source(spec.float_modifiers, false); break;  // no c_abs bit
        case Operand::kImm: i.imm = interesting_int(rng_); break;
        case Operand::kFimm: i.imm = interesting_float(rng_); break;
        default: break;
      }
    }
    return i;
  }
  Instruction random_compute() { return compute(*compute_[rng_.below(static_cast<std::uint32_t>(compute_.size()))]); }

  static Statement single(const Instruction& i, std::string note = {}) {
    Statement s;
    s.kind = StatementKind::kInstruction;
    s.insns = {i};
    s.note = std::move(note);
    return s;
  }

  // ---- routines ----

  void make_routines() {
    const int n = rng_.range(0, std::min(o_.max_routines, o_.machine.call_depth));
    p_.routines.resize(static_cast<std::size_t>(n));
    int shaders = 0, functions = 0;
    for (Routine& r : p_.routines) {
      r.shader = rng_.chance(50);
      r.label = r.shader ? fmt::format("hit_s{}", shaders++) : fmt::format("f{}", functions++);
      r.keeps_return_address = rng_.chance(40);
      r.return_register = static_cast<std::uint8_t>(free_reg());
      r.return_lane = static_cast<std::uint8_t>(rng_.below(4));
    }
    costs_.emplace(p_);
    const std::uint32_t slots = o_.machine.stack_bytes / 16;
    for (int i = n - 1; i >= 0; --i) {
      Routine& r = p_.routines[static_cast<std::size_t>(i)];
      const std::uint32_t keeps = r.keeps_return_address ? 1 : 0;
      const auto returns = static_cast<std::uint32_t>(o_.machine.call_depth - 1);
      const Scope scope{i, !r.keeps_return_address, 0, {o_.max_instructions / 6, slots - keeps, returns}};
      r.body = block(scope, rng_.range(1, o_.max_statements));
      costs_->update(p_, i);
    }
  }

  // ---- blocks and statements ----

  std::vector<Statement> block(const Scope& scope, int statements) {
    std::vector<Statement> out;
    Cost room = scope.room;
    for (int n = 0; n < statements; ++n) {
      // A few tries for a statement that fits what is left; then the block ends.
      bool placed = false;
      for (int attempt = 0; attempt < 4 && !placed; ++attempt) {
        Scope here = scope;
        here.room = room;
        std::optional<Statement> s = statement(here);
        if (!s) continue;
        const Cost c = costs_->statement(*s);
        if (c.instructions > room.instructions || c.stack > room.stack || c.returns > room.returns) continue;
        room.instructions -= c.instructions;
        out.push_back(std::move(*s));
        placed = true;
      }
      if (!placed) break;
    }
    return out;
  }

  enum class Choice { kCompute, kLoad, kIndexedLoad, kStore, kSpecial, kRay, kIf, kLoop, kCall, kCalli, kPushPop,
                      kReturnAddress, kEarlyHalt };

  std::optional<Statement> statement(const Scope& scope) {
    static constexpr std::array<std::pair<Choice, int>, 13> kWeights{{
        {Choice::kCompute, 40}, {Choice::kLoad, 9}, {Choice::kIndexedLoad, 5}, {Choice::kStore, 5},
        {Choice::kSpecial, 3}, {Choice::kRay, 5}, {Choice::kIf, 8}, {Choice::kLoop, 5}, {Choice::kCall, 8},
        {Choice::kCalli, 6}, {Choice::kPushPop, 4}, {Choice::kReturnAddress, 3}, {Choice::kEarlyHalt, 1},
    }};
    int total = 0;
    for (const auto& [choice, weight] : kWeights) total += weight;
    int r = static_cast<int>(rng_.below(static_cast<std::uint32_t>(total)));
    Choice choice = Choice::kCompute;
    for (const auto& [c, weight] : kWeights) {
      if (r < weight) {
        choice = c;
        break;
      }
      r -= weight;
    }
    const bool nest = scope.depth < o_.max_nesting;
    switch (choice) {
      case Choice::kCompute: return single(random_compute());
      case Choice::kLoad: return load();
      case Choice::kIndexedLoad: return indexed_load();
      case Choice::kStore: return store();
      case Choice::kSpecial: return special();
      case Choice::kRay: return ray();
      case Choice::kIf: return nest ? std::optional(if_else(scope)) : std::nullopt;
      case Choice::kLoop: return nest ? loop(scope) : std::nullopt;
      case Choice::kCall: return call(scope);
      case Choice::kCalli: return calli(scope);
      case Choice::kPushPop: return nest ? push_pop(scope) : std::nullopt;
      case Choice::kReturnAddress: return scope.return_address ? std::optional(return_address()) : std::nullopt;
      case Choice::kEarlyHalt: return o_.fault == FaultClass::kNone ? std::optional(early_halt()) : std::nullopt;
    }
    return std::nullopt;
  }

  Scope inner(const Scope& scope, std::uint64_t instructions, std::uint32_t stack) const {
    Scope s = scope;
    ++s.depth;
    s.room.instructions = instructions;
    s.room.stack = scope.room.stack >= stack ? scope.room.stack - stack : 0;
    return s;
  }

  // A load from a segment every launch has, at an offset inside it.
  Statement load() {
    const Opcode op = rng_.pick(std::span<const Opcode>(kLoads));
    const std::uint32_t bytes = load_bytes(op);
    const int segment = static_cast<int>(rng_.below(4));
    const auto aligned_below = [&](std::uint32_t size) { return 4 * rng_.below((size - bytes) / 4 + 1); };
    std::uint32_t offset = 0;
    std::string note;
    switch (segment) {
      case kBaseFramebuffer:
        offset = aligned_below(mm::kFramebufferBytesPerPixel);
        note = "own framebuffer pixel";
        break;
      case kBaseLaunch:
        // The launch block's fixed part: the shader table after it shrinks with the shaders.
        offset = aligned_below(mm::kLaunchBytes);
        note = "launch block";
        break;
      case kBaseData:
        offset = aligned_below(static_cast<std::uint32_t>(4 * p_.data.size()));
        note = fmt::format("values + {}", offset);
        break;
      default:
        offset = aligned_below(kImageHeaderBytes);
        note = fmt::format("image header + {}", offset);
        break;
    }
    return single(make_instruction(op, free_reg(), write_mask(), base(segment), {}, {}, offset), note);
  }

  // A load whose address is computed: lane-dependent in .data, or a record the launch
  // block points at.
  Statement indexed_load() {
    const Opcode op = rng_.pick(std::span<const Opcode>(kLoads));
    const std::uint32_t bytes = load_bytes(op);
    const int t = free_reg();
    Statement s;
    s.kind = StatementKind::kIndexedLoad;
    std::uint32_t offset = 0;
    if (rng_.chance(50)) {
      const std::uint32_t mask = rng_.chance(50) ? 3 : 7;
      const int coordinate = static_cast<int>(rng_.below(3));  // x, y or index
      s.insns = {make_instruction(Opcode::kAndi, t, lane_bit(0), pixel_lane(coordinate), {}, {}, mask),
                 make_instruction(Opcode::kShli, t, lane_bit(0), reg(t, broadcast(0)), {}, {}, 2),
                 make_instruction(Opcode::kIadd, t, lane_bit(0), reg(t, broadcast(0)), base(kBaseData))};
      const auto room = static_cast<std::uint32_t>(4 * p_.data.size()) - bytes - 4 * mask;
      offset = 4 * rng_.below(room / 4 + 1);
      s.note = fmt::format("load from values + 4 * (pixel {} & {}) + {}", "xyz"[coordinate], mask, offset);
    } else {
      const RecordPointer& r = rng_.pick(std::span<const RecordPointer>(kRecordPointers));
      s.insns = {make_instruction(Opcode::kLd1, t, lane_bit(0), base(kBaseLaunch), {}, {}, r.at)};
      offset = 4 * rng_.below((r.bytes - bytes) / 4 + 1);
      s.note = fmt::format("load from the {} + {}", r.name, offset);
    }
    s.insns.push_back(make_instruction(op, free_reg(), write_mask(), reg(t, swizzle_reading(0)), {}, {}, offset));
    return s;
  }

  Statement store() {
    const int data = source_reg();
    if (rng_.chance(50)) {
      return single(make_instruction(Opcode::kSt, data, write_mask(), base(kBaseFramebuffer)),
                    "own framebuffer pixel");
    }
    return single(make_instruction(Opcode::kSt1, data, lane_bit(0), base(kBaseFramebuffer), {}, {}, 4 * rng_.below(4)),
                  "own framebuffer pixel");
  }

  Statement special() {
    const si::SpecialSpec& sr = rng_.pick(std::span<const si::SpecialSpec>(si::kSpecials));
    return single(make_instruction(Opcode::kRdsr, free_reg(), write_mask(), {}, {}, {},
                                   static_cast<std::uint32_t>(sr.index)));
  }

  // A ray from the launch block's camera towards a point of the scene's box or through a
  // point of the image plane (either possibly lane-dependent), so that some rays hit and
  // some miss; or a ray of whatever two registers hold (NaN, inf, zero directions: the
  // units must take anything).
  Statement ray() {
    const Opcode op = rng_.chance(50) ? Opcode::kTrace : Opcode::kTracea;
    const std::string_view mnemonic = isa::find_insn(op)->mnemonic;
    Statement g;
    g.kind = StatementKind::kGroup;
    if (rng_.chance(15)) {
      g.note = fmt::format("{} of a ray from registers", mnemonic);
      g.body.push_back(single(make_instruction(op, free_reg(), write_mask(), reg(source_reg(), swizzle()),
                                               reg(source_reg(), swizzle()))));
      return g;
    }
    std::array<int, 4> r{};  // origin, direction, scratch, coordinates: four distinct free registers
    for (auto at = r.begin(); at != r.end(); ++at) {
      do {
        *at = free_reg();
      } while (std::find(r.begin(), at, *at) != at);
    }
    const auto [origin, direction, scratch, coordinate] = r;
    const auto lif = [&](int d, int mask, float value) {
      return make_instruction(Opcode::kLif, d, mask, {}, {}, {}, std::bit_cast<std::uint32_t>(value));
    };
    const auto add = [&](const Instruction& i, std::string note = {}) { g.body.push_back(single(i, std::move(note))); };
    isa::Source minus_origin = reg(origin);
    minus_origin.neg = true;
    std::string where;
    float t_max = std::numeric_limits<float>::infinity(), t_min = 0.0f;
    if (rng_.chance(55)) {
      // Towards bounds_lo + f (bounds_hi - bounds_lo), reached at t = 1. The scene
      // record's box is in kd space, which is the camera's space in the image of a scene
      // in chip space (functional::chip_space_scene, what the Runner builds).
      // One statement: the loads through the pointer are legal only after it.
      Statement box;
      box.kind = StatementKind::kIndexedLoad;
      box.insns = {make_instruction(Opcode::kLd1, coordinate, lane_bit(0), base(kBaseLaunch), {}, {},
                                    mm::kLaunchSceneAt),
                   make_instruction(Opcode::kLdf, scratch, isa::kAllLanes, reg(coordinate, broadcast(0)), {}, {},
                                    mm::kSceneRecordBoundsLoAt),
                   make_instruction(Opcode::kLdf, direction, isa::kAllLanes, reg(coordinate, broadcast(0)), {}, {},
                                    mm::kSceneRecordBoundsHiAt)};
      box.note = "the scene record's bounds_lo and bounds_hi";
      g.body.push_back(std::move(box));
      isa::Source minus_lo = reg(scratch);
      minus_lo.neg = true;
      add(make_instruction(Opcode::kAdd, direction, isa::kAllLanes, reg(direction), minus_lo), "the box's extent");
      std::array<float, 3> f{};
      for (float& v : f) v = static_cast<float>(rng_.range(2, 8)) / 10.0f;
      if (rng_.chance(50)) {
        // f.x = pixel index / 16: the lanes aim at different points.
        add(make_instruction(Opcode::kI2f, coordinate, lane_bit(0), pixel_lane(2)));
        add(lif(coordinate, lane_bit(3), 0.0625f));
        add(make_instruction(Opcode::kMul, coordinate, lane_bit(0), reg(coordinate, broadcast(0)),
                             reg(coordinate, broadcast(3))));
        add(lif(coordinate, lane_bit(1), f[1]));
        add(lif(coordinate, lane_bit(2), f[2]));
        where = fmt::format("the scene box's point (pixel index / 16, {}, {})", f[1], f[2]);
      } else {
        for (int k = 0; k < 3; ++k) add(lif(coordinate, lane_bit(k), f[static_cast<std::size_t>(k)]));
        where = fmt::format("the scene box's point ({}, {}, {})", f[0], f[1], f[2]);
      }
      add(make_instruction(Opcode::kMad, direction, 0x7, reg(direction), reg(coordinate), reg(scratch)));
      add(make_instruction(Opcode::kLdf, origin, isa::kAllLanes, base(kBaseLaunch), {}, {}, mm::kLaunchOriginAt),
          "w = 0: t_min 0");
      add(make_instruction(Opcode::kAdd, direction, 0x7, reg(direction), minus_origin));
      // Short of the point, just past it, or from it on.
      static constexpr std::array<float, 3> kTMax{0.5f, 1.0f, 2.0f};
      if (rng_.chance(35)) t_max = rng_.pick(std::span<const float>(kTMax));
      if (rng_.chance(15)) t_min = 1.0f;
    } else {
      add(make_instruction(Opcode::kLdf, origin, isa::kAllLanes, base(kBaseLaunch), {}, {}, mm::kLaunchOriginAt),
          "w = 0: t_min 0");
      add(make_instruction(Opcode::kLdf, direction, isa::kAllLanes, base(kBaseLaunch), {}, {}, mm::kLaunchForwardAt));
      where = "the image plane at";
      for (const auto& [axis, at] : {std::pair{"x", mm::kLaunchRightAt}, std::pair{"y", mm::kLaunchUpAt}}) {
        if (rng_.chance(50)) {
          // Across the launch: coordinate = pixel x (or y) * scale + offset.
          static constexpr std::array<float, 3> kScale{0.25f, 0.5f, 1.0f};
          static constexpr std::array<float, 4> kOffset{-1.0f, -0.75f, -0.5f, 0.0f};
          const float scale = rng_.pick(std::span<const float>(kScale));
          const float offset = rng_.pick(std::span<const float>(kOffset));
          add(make_instruction(Opcode::kI2f, coordinate, lane_bit(0), pixel_lane(axis[0] == 'x' ? 0 : 1)));
          add(lif(coordinate, lane_bit(1), scale));
          add(lif(coordinate, lane_bit(2), offset));
          add(make_instruction(Opcode::kMad, coordinate, lane_bit(0), reg(coordinate, broadcast(0)),
                               reg(coordinate, broadcast(1)), reg(coordinate, broadcast(2))));
          where += fmt::format(" {} = pixel {} * {} + {}", axis, axis, scale, offset);
        } else {
          const float value = static_cast<float>(rng_.range(-12, 12)) / 10.0f;
          add(lif(coordinate, lane_bit(0), value));
          where += fmt::format(" {} = {}", axis, value);
        }
        add(make_instruction(Opcode::kLdf, scratch, isa::kAllLanes, base(kBaseLaunch), {}, {}, at));
        add(make_instruction(Opcode::kMad, direction, 0x7, reg(scratch), reg(coordinate, broadcast(0)),
                             reg(direction)));
      }
      if (rng_.chance(10)) t_max = 1e-3f;
    }
    if (rng_.chance(10)) {
      isa::Source away = reg(direction);
      away.neg = true;
      add(make_instruction(Opcode::kMov, direction, 0x7, away), "away from the scene");
    }
    add(lif(direction, lane_bit(3), t_max), "t_max");
    if (t_min != 0.0f) add(lif(origin, lane_bit(3), t_min), "t_min");
    add(make_instruction(op, free_reg(), write_mask(), reg(origin), reg(direction)));
    g.note = fmt::format("{} of a camera ray towards {}", mnemonic, where);
    return g;
  }

  Condition condition() {
    Condition c;
    c.reg = static_cast<std::uint8_t>(free_reg());
    const int lane = static_cast<int>(rng_.below(4));
    c.swizzle = swizzle_reading(lane);
    c.when_zero = rng_.chance(50);
    const int mask = lane_bit(lane) | (rng_.chance(30) ? write_mask() : 0);
    const auto pick_op = [&](std::initializer_list<Opcode> ops) {
      return *(ops.begin() + rng_.below(static_cast<std::uint32_t>(ops.size())));
    };
    switch (rng_.below(6)) {
      case 0: {
        const std::uint32_t m = 1 + rng_.below(7);
        c.setup = {make_instruction(Opcode::kAndi, c.reg, mask, pixel_lane(2), {}, {}, m)};
        c.text = fmt::format("pixel index & {}", m);
        break;
      }
      case 1: {
        const int axis = static_cast<int>(rng_.below(2));
        c.setup = {make_instruction(Opcode::kAndi, c.reg, mask, pixel_lane(axis), {}, {}, 1)};
        c.text = fmt::format("pixel {} odd", "xy"[axis]);
        break;
      }
      case 2: {
        const int t = free_reg();
        c.setup = {make_instruction(Opcode::kRdsr, t, isa::kAllLanes, {}, {}, {}, si::kSpecialThread),
                   make_instruction(Opcode::kAndi, c.reg, mask, reg(t, broadcast(3)), {}, {}, 1)};
        c.text = "odd lane within the chunk";
        break;
      }
      case 3: {
        const std::uint32_t k = 1 + rng_.below(static_cast<std::uint32_t>(2 * o_.machine.chunk_size));
        c.setup = {make_instruction(Opcode::kIlti, c.reg, mask, pixel_lane(2), {}, {}, k)};
        c.text = fmt::format("pixel index < {}", k);
        break;
      }
      case 4: {
        const Opcode op = pick_op({Opcode::kFlt, Opcode::kFle, Opcode::kFeq, Opcode::kFne});
        c.setup = {make_instruction(op, c.reg, mask, source(true, true), source(true, true))};
        c.text = fmt::format("{} of two registers", isa::find_insn(op)->mnemonic);
        break;
      }
      default: {
        const Opcode op = pick_op({Opcode::kIeq, Opcode::kIlt, Opcode::kIltu});
        c.setup = {make_instruction(op, c.reg, mask, source(false, false), source(false, false))};
        c.text = fmt::format("{} of two registers", isa::find_insn(op)->mnemonic);
        break;
      }
    }
    if (c.when_zero) c.text = fmt::format("not ({})", c.text);
    return c;
  }

  Statement if_else(const Scope& scope) {
    Statement s;
    s.kind = StatementKind::kIf;
    s.condition = condition();
    const std::uint64_t room = scope.room.instructions > 8 ? (scope.room.instructions - 8) / 2 : 0;
    s.body = block(inner(scope, room, 0), rng_.range(1, o_.max_statements));
    if (rng_.chance(60)) s.other = block(inner(scope, room, 0), rng_.range(1, o_.max_statements));
    return s;
  }

  std::optional<Statement> loop(const Scope& scope) {
    Statement s;
    s.kind = StatementKind::kLoop;
    const int counter = p_.regs.counter;
    const std::uint32_t most = std::max<std::uint32_t>(o_.max_loop_trips, 1);
    if (rng_.chance(50) && most >= 2) {
      // 1 + (pixel coordinate & mask) trips: the lanes leave the loop at different times.
      const std::uint32_t mask = most >= 4 && rng_.chance(50) ? 3 : 1;
      const int coordinate = static_cast<int>(rng_.below(3));
      s.insns = {make_instruction(Opcode::kAndi, counter, lane_bit(0), pixel_lane(coordinate), {}, {}, mask),
                 make_instruction(Opcode::kIaddi, counter, lane_bit(0), reg(counter, broadcast(0)), {}, {}, 1)};
      s.trips = mask + 1;
      s.note = fmt::format("1 + (pixel {} & {}) trips", "xyz"[coordinate], mask);
    } else {
      s.trips = 1 + rng_.below(most);
      s.insns = {make_instruction(Opcode::kLi, counter, lane_bit(0), {}, {}, {}, s.trips)};
      s.note = fmt::format("{} trip{}", s.trips, s.trips == 1 ? "" : "s");
    }
    if (scope.room.stack < 1) return std::nullopt;
    const std::uint64_t overhead = 4 + s.insns.size();
    if (scope.room.instructions < overhead + 3 * s.trips) return std::nullopt;
    const std::uint64_t body = (scope.room.instructions - overhead) / s.trips - 2;
    s.body = block(inner(scope, body, 1), rng_.range(1, o_.max_statements));
    return s;
  }

  std::optional<Statement> call(const Scope& scope) {
    const int first = scope.routine + 1;
    const int n = static_cast<int>(p_.routines.size());
    if (first >= n) return std::nullopt;
    Statement s;
    s.kind = StatementKind::kCall;
    s.routine = rng_.range(first, n - 1);
    return s;
  }

  std::optional<Statement> calli(const Scope& scope) {
    // Shader ids of routines after this one: the ids are in routine order.
    int id = 0, lo = -1;
    for (int i = 0; i < static_cast<int>(p_.routines.size()); ++i) {
      if (!p_.routines[static_cast<std::size_t>(i)].shader) continue;
      if (i > scope.routine && lo < 0) lo = id;
      ++id;
    }
    if (lo < 0) return std::nullopt;
    const int count = id;
    Statement s;
    s.kind = StatementKind::kCalli;
    const int t = free_reg();
    const int lane = static_cast<int>(rng_.below(4));
    s.shader_lo = lo + static_cast<int>(rng_.below(static_cast<std::uint32_t>(count - lo)));
    if (s.shader_lo + 1 < count && rng_.chance(60)) {
      // Lanes of odd pixels call the next shader: the chunk diverges into two routines.
      s.shader_hi = s.shader_lo + 1;
      s.insns = {make_instruction(Opcode::kAndi, t, lane_bit(lane), pixel_lane(2), {}, {}, 1),
                 make_instruction(Opcode::kIaddi, t, lane_bit(lane), reg(t, broadcast(lane)), {}, {},
                                  static_cast<std::uint32_t>(s.shader_lo))};
      s.note = fmt::format("calli shader {} + (pixel index & 1)", s.shader_lo);
    } else {
      s.shader_hi = s.shader_lo;
      s.insns = {make_instruction(Opcode::kLi, t, lane_bit(lane), {}, {}, {}, static_cast<std::uint32_t>(s.shader_lo))};
      s.note = fmt::format("calli shader {}", s.shader_lo);
    }
    s.insns.push_back(make_instruction(Opcode::kCalli, 0, 0, reg(t, swizzle_reading(lane))));
    return s;
  }

  std::optional<Statement> push_pop(const Scope& scope) {
    const int pushes = rng_.range(1, 2);
    if (scope.room.stack < static_cast<std::uint32_t>(pushes) || scope.room.instructions < 2u * pushes + 1) {
      return std::nullopt;
    }
    Statement s;
    s.kind = StatementKind::kPushPop;
    for (int i = 0; i < pushes; ++i) {
      s.insns.push_back(make_instruction(Opcode::kPush, 0, 0, reg(source_reg(), swizzle())));
    }
    for (int i = 0; i < pushes; ++i) s.insns.push_back(make_instruction(Opcode::kPop, free_reg(), write_mask()));
    s.body = block(inner(scope, scope.room.instructions - 2u * pushes, static_cast<std::uint32_t>(pushes)),
                   rng_.range(0, o_.max_statements));
    s.note = fmt::format("{} push{} and as many pops", pushes, pushes > 1 ? "es" : "");
    return s;
  }

  Statement return_address() {
    Statement s;
    s.kind = StatementKind::kReturnAddress;
    const int r = free_reg();
    const int lane = static_cast<int>(rng_.below(4));
    const int mask = lane_bit(lane) | (rng_.chance(50) ? write_mask() : 0);
    s.insns = {make_instruction(Opcode::kMfra, r, mask),
               make_instruction(Opcode::kMtra, 0, 0, reg(r, swizzle_reading(lane)))};
    s.note = "the return address out of the return stack and back";
    return s;
  }

  Statement early_halt() {
    Statement s;
    s.kind = StatementKind::kIf;
    s.condition = condition();
    Statement halt;
    halt.kind = StatementKind::kHalt;
    halt.note = "early: these lanes end their pixel here";
    s.body = {halt};
    return s;
  }

  // ---- faults ----

  // The fault code inside a condition on the pixel index, so that some lanes fault and
  // others run on (pixel 0 always halts unless every pixel faults).
  Statement fault_statement() {
    Statement f;
    f.kind = StatementKind::kFault;
    f.fault = fault_code(o_.fault);
    // Reading another pixel's framebuffer faults only where that pixel is not the own:
    // pixel 0 must not run it.
    const bool every_pixel_allowed = o_.fault != FaultClass::kOutOfRangeOtherPixel;
    const std::uint32_t kind = rng_.below(every_pixel_allowed ? 4 : 3);
    if (kind == 3) return f;
    Statement s;
    s.kind = StatementKind::kIf;
    Condition& c = s.condition;
    c.reg = static_cast<std::uint8_t>(free_reg());
    const int lane = static_cast<int>(rng_.below(4));
    c.swizzle = swizzle_reading(lane);
    c.first_pixel = 1;
    switch (kind) {
      case 0:
        c.setup = {make_instruction(Opcode::kAndi, c.reg, lane_bit(lane), pixel_lane(2), {}, {}, 1)};
        c.text = "odd pixel index";
        break;
      case 1:
        c.setup = {make_instruction(Opcode::kIlti, c.reg, lane_bit(lane), pixel_lane(2), {}, {}, 1)};
        c.when_zero = true;
        c.text = "pixel index >= 1";
        break;
      default:
        c.setup = {make_instruction(Opcode::kIaddi, c.reg, lane_bit(lane), pixel_lane(2), {}, {}, 0xffffffffu)};
        c.when_zero = true;
        c.text = "pixel index == 1";
        break;
    }
    s.body = {f};
    return s;
  }

  FaultCode fault_code(FaultClass fault) {
    FaultCode c;
    c.fault = fault;
    const int t = free_reg(), x = free_reg();
    const auto word = [](const Instruction& i) { return isa::encode(i); };
    const std::uint32_t data_bytes = static_cast<std::uint32_t>(4 * p_.data.size());
    const auto any_load = [&] { return rng_.pick(std::span<const Opcode>(kLoads)); };
    // A load, or a store of lane x, at [r + offset].
    // st's lane i goes to offset + 4i: it takes only the offset's misalignment (offset %
    // 4), so that its lanes stay within the 16 bytes the other forms reach.
    const auto access = [&](isa::Source address, std::uint32_t offset, bool store) {
      if (!store) return make_instruction(any_load(), x, write_mask(), address, {}, {}, offset);
      return rng_.chance(50) ? make_instruction(Opcode::kSt1, x, lane_bit(0), address, {}, {}, offset)
                             : make_instruction(Opcode::kSt, x, static_cast<int>(1 + rng_.below(15)), address, {}, {},
                                                offset % 4);
    };
    switch (fault) {
      case FaultClass::kNone: break;
      case FaultClass::kIllegalOpcode: {
        std::vector<std::uint64_t> unknown;
        for (std::uint64_t op = 0; op < (1u << si::kOpcodeField.width); ++op) {
          if (!isa::find_insn(static_cast<Opcode>(op))) unknown.push_back(op);
        }
        const std::uint64_t op = rng_.pick(std::span<const std::uint64_t>(unknown));
        c.before = {op | (rng_.chance(50) ? rng_.next() << si::kOpcodeField.width : 0)};
        c.text = fmt::format("opcode {:#04x}, which no instruction has", op);
        break;
      }
      case FaultClass::kIllegalUnusedField: {
        std::vector<const si::InsnSpec*> with_unused;
        for (const si::InsnSpec& s : si::kInsns) {
          if (~s.used_bits) with_unused.push_back(&s);
        }
        const si::InsnSpec& s = *rng_.pick(std::span<const si::InsnSpec* const>(with_unused));
        std::uint64_t w = isa::encode(make_instruction(s.opcode)) | (rng_.next() & s.used_bits);
        w = (w & ~((std::uint64_t{1} << si::kOpcodeField.width) - 1)) | static_cast<std::uint64_t>(s.opcode);
        std::uint32_t bit = 0;
        do {
          bit = rng_.below(64);
        } while (s.used_bits >> bit & 1);
        c.before = {w | std::uint64_t{1} << bit};
        c.text = fmt::format("{} with bit {} set, which it does not use", s.mnemonic, bit);
        break;
      }
      case FaultClass::kIllegalRegister: {
        const int bad = rng_.range(o_.machine.registers, 63);
        Instruction i = random_compute();
        std::vector<std::uint8_t*> fields;
        for (int k = 0; k < i.spec->operand_count; ++k) {
          switch (i.spec->operands[static_cast<std::size_t>(k)]) {
            case Operand::kD: fields.push_back(&i.dst); break;
            case Operand::kA: fields.push_back(&i.src[0].reg); break;
            case Operand::kB: fields.push_back(&i.src[1].reg); break;
            case Operand::kC: fields.push_back(&i.src[2].reg); break;
            default: break;
          }
        }
        *fields[rng_.below(static_cast<std::uint32_t>(fields.size()))] = static_cast<std::uint8_t>(bad);
        c.before = {word(i)};
        c.text = fmt::format("r{}, past the {} registers", bad, o_.machine.registers);
        break;
      }
      case FaultClass::kIllegalSt1Mask: {
        int mask = 0;
        do {
          mask = static_cast<int>(rng_.below(16));
        } while (mask == lane_bit(0));
        c.before = {word(make_instruction(Opcode::kSt1, x, mask, base(kBaseFramebuffer), {}, {}, 4 * rng_.below(4)))};
        c.text = "st1 with a write mask other than .x";
        break;
      }
      case FaultClass::kIllegalSpecial: {
        std::uint32_t index = 0;
        do {
          index = rng_.chance(50) ? static_cast<std::uint32_t>(si::kSpecials.size()) + rng_.below(60) : rng_.u32();
        } while (std::any_of(si::kSpecials.begin(), si::kSpecials.end(),
                             [&](const si::SpecialSpec& s) { return static_cast<std::uint32_t>(s.index) == index; }));
        c.before = {word(make_instruction(Opcode::kRdsr, x, write_mask(), {}, {}, {}, index))};
        c.text = fmt::format("rdsr of special register {}, which does not exist", index);
        break;
      }
      case FaultClass::kMisaligned: {
        const bool store = rng_.chance(30);
        const int segment = store ? kBaseFramebuffer : static_cast<int>(rng_.below(4));
        c.before = {word(access(base(segment), 4 * rng_.below(2) + 1 + rng_.below(3), store))};
        c.text = "an address that is not a multiple of 4";
        break;
      }
      case FaultClass::kOutOfRangeUnmapped: {
        static constexpr std::array<std::uint32_t, 5> kUnmapped{0x30000000u, 0x3ffffff0u, 0x48000000u, 0x5ff00000u,
                                                                0xf0000000u};
        const std::uint32_t address = rng_.pick(std::span<const std::uint32_t>(kUnmapped));
        c.before = {word(make_instruction(Opcode::kLi, t, lane_bit(0), {}, {}, {}, address)),
                    word(access(reg(t, broadcast(0)), 0, rng_.chance(30)))};
        c.text = fmt::format("address {:#010x}, in no segment", address);
        break;
      }
      case FaultClass::kOutOfRangeSegmentEnd: {
        const Opcode load16 = rng_.chance(50) ? Opcode::kLd : Opcode::kLdf;
        switch (rng_.below(3)) {
          case 0:
            c.before = {word(make_instruction(Opcode::kRdsr, t, isa::kAllLanes, {}, {}, {}, si::kSpecialParams)),
                        word(make_instruction(Opcode::kIadd, t, lane_bit(0), reg(t, broadcast(0)),
                                              reg(t, broadcast(1)))),
                        word(make_instruction(load16, x, write_mask(), reg(t, broadcast(0)), {}, {}, 0xfffffff8u))};
            c.text = "16 bytes from 8 before the end of the launch block (rdsr params)";
            break;
          case 1:
            c.before = {word(make_instruction(load16, x, write_mask(), base(kBaseData), {}, {}, data_bytes - 8))};
            c.text = "16 bytes from 8 before the end of .data";
            break;
          default:
            c.before = {word(make_instruction(Opcode::kLd1, t, lane_bit(0), base(kBaseImage), {}, {},
                                              mm::kHeaderTotalBytesAt)),
                        word(make_instruction(load16, x, write_mask(), reg(t, broadcast(0)), {}, {}, 0xfffffffcu))};
            c.text = "16 bytes from 4 before the end of the image (its header's total_bytes)";
            break;
        }
        break;
      }
      case FaultClass::kOutOfRangeReadOnly: {
        const int segment = rng_.range(kBaseLaunch, kBaseImage);
        const std::uint32_t size = segment == kBaseData ? data_bytes : segment == kBaseLaunch ? mm::kLaunchBytes
                                                                                                 : kImageHeaderBytes;
        c.before = {word(access(base(segment), 4 * rng_.below((size - 16) / 4 + 1), true))};
        c.text = "a store to a read-only segment";
        break;
      }
      case FaultClass::kOutOfRangeOtherPixel:
        c.before = {word(make_instruction(Opcode::kLi, t, lane_bit(0), {}, {}, {}, mm::kDeviceFramebufferBase)),
                    word(access(reg(t, broadcast(0)), 4 * rng_.below(4), rng_.chance(50)))};
        c.text = "pixel 0's framebuffer bytes";
        break;
      case FaultClass::kOutOfRangeStack:
        c.before = {word(make_instruction(Opcode::kLi, t, lane_bit(0), {}, {}, {},
                                          mm::kDeviceStackBase + 16 * rng_.below(64))),
                    word(access(reg(t, broadcast(0)), 0, rng_.chance(30)))};
        c.text = "an address in the stack segment, which only push and pop reach";
        break;
      case FaultClass::kStackOverflow:
        c.repeat = o_.machine.stack_bytes / 16 + 1;
        c.repeated = {word(make_instruction(Opcode::kPush, 0, 0, reg(source_reg(), swizzle())))};
        c.text = fmt::format("{} pushes, one more than the stack holds", c.repeat);
        break;
      case FaultClass::kStackUnderflow:
        c.after = {word(make_instruction(Opcode::kPop, x, write_mask()))};
        c.text = "a pop with nothing pushed";
        break;
      case FaultClass::kCallDepthOverflow: {
        c.before = {word(make_instruction(Opcode::kLi, t, lane_bit(0), {}, {}, {}, 0))};
        c.repeat = static_cast<std::uint32_t>(o_.machine.call_depth);
        c.repeated = {word(make_instruction(Opcode::kMtra, 0, 0, reg(t, swizzle_reading(0))))};
        const bool has_shader =
            std::any_of(p_.routines.begin(), p_.routines.end(), [](const Routine& r) { return r.shader; });
        switch (rng_.below(has_shader ? 3 : 2)) {
          case 0:
            c.after = {word(make_instruction(Opcode::kMtra, 0, 0, reg(t, swizzle_reading(0))))};
            c.text = "mtra";
            break;
          case 1:
            // Never reached: the call faults before it jumps.
            c.after = {word(make_instruction(Opcode::kCall, 0, 0, {}, {}, {}, 0))};
            c.text = "call";
            break;
          default:
            c.after = {word(make_instruction(Opcode::kCalli, 0, 0, reg(t, swizzle_reading(0))))};
            c.text = "calli of shader 0";
            break;
        }
        c.text = fmt::format("{} mtra fill the return stack, then {}", c.repeat, c.text);
        break;
      }
      case FaultClass::kReturnStackEmpty:
        c.after = {rng_.chance(50) ? word(make_instruction(Opcode::kRet))
                                   : word(make_instruction(Opcode::kMfra, x, static_cast<int>(1 + rng_.below(15))))};
        c.text = "ret or mfra in raygen, whose return stack is empty";
        break;
      case FaultClass::kShaderId: {
        const auto shaders = static_cast<std::uint32_t>(
            std::count_if(p_.routines.begin(), p_.routines.end(), [](const Routine& r) { return r.shader; }));
        const int lane = static_cast<int>(rng_.below(4));
        const std::uint32_t id = rng_.chance(25) ? 0xffffffffu : shaders + rng_.below(4);
        c.before = {word(make_instruction(Opcode::kLi, t, lane_bit(lane), {}, {}, {}, id)),
                    word(make_instruction(Opcode::kCalli, 0, 0, reg(t, swizzle_reading(lane))))};
        c.text = fmt::format("calli of shader {} with {} shaders in the table", id, shaders);
        break;
      }
      case FaultClass::kWatchdog:
        c.repeat = static_cast<std::uint32_t>(o_.watchdog);
        c.text = fmt::format("a loop of {} trips, 2 instructions each, past the watchdog", c.repeat);
        break;
      case FaultClass::kSpin: {
        const std::uint32_t branches = rng_.below(3);
        for (std::uint32_t i = 0; i < branches; ++i) {
          c.spin_branches.push_back(make_instruction(rng_.chance(50) ? Opcode::kBz : Opcode::kBnz, 0, 0,
                                                     reg(source_reg(), swizzle())));
        }
        c.spin = true;
        c.text = fmt::format("a loop of {} branch{} that writes nothing", branches + 1, branches == 0 ? "" : "es");
        break;
      }
      case FaultClass::kPc:
        c.branch_past_end = true;
        c.text = "a branch past the last instruction";
        break;
    }
    return c;
  }

  Random rng_;
  Options o_;
  Program p_;
  std::optional<CostModel> costs_;
  std::vector<const si::InsnSpec*> compute_;
};

}  // namespace

// Read from spec/isa.toml's table, so that a new instruction of this kind is generated
// without a change here; one with another effect is not, and the coverage test names it.
// mfra and mtra look like one but move the return stack: the routines and
// kReturnAddress use them.
bool is_pure_compute(const si::InsnSpec& spec) {
  if (spec.cls != si::Class::kFpu && spec.cls != si::Class::kSfu && spec.cls != si::Class::kInt) return false;
  if (spec.opcode == Opcode::kMfra || spec.opcode == Opcode::kMtra) return false;
  for (int k = 0; k < spec.operand_count; ++k) {
    switch (spec.operands[static_cast<std::size_t>(k)]) {
      case Operand::kD:
      case Operand::kA:
      case Operand::kB:
      case Operand::kC:
      case Operand::kImm:
      case Operand::kFimm: break;
      default: return false;
    }
  }
  return true;
}

Options Options::for_config(const spec::HardwareConfig& config) {
  Options o;
  o.machine.registers = config.registers;
  o.machine.chunk_size = config.chunk_size;
  o.machine.call_depth = config.call_depth;
  o.machine.stack_bytes = static_cast<std::uint32_t>(config.stack_bytes);
  return o;
}

Program generate(std::uint64_t seed, const Options& options) { return Generator(seed, options).run(); }

}  // namespace rpu::progen
