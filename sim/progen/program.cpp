#include "progen/program.hpp"

#include <algorithm>
#include <span>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "progen/make_instruction.hpp"

namespace rpu::progen {

using isa::Opcode;

RegisterPlan RegisterPlan::for_registers(int registers) {
  RegisterPlan p;
  p.pixel = static_cast<std::uint8_t>(registers - 1);
  p.bases = static_cast<std::uint8_t>(registers - 2);
  p.counter = static_cast<std::uint8_t>(registers - 3);
  p.free = registers - 3;
  return p;
}

namespace {

// The prologue every raygen starts with: it fills the registers of the RegisterPlan.
constexpr std::uint64_t kPrologueInstructions = 7;

class Writer {
 public:
  explicit Writer(const Program& p) : p_(p) {}

  std::string text() && { return std::move(out_); }

  void comment(std::string_view text) { out_ += fmt::format("        ; {}\n", text); }
  void label(std::string_view name, std::string_view note = {}) {
    out_ += note.empty() ? fmt::format("{}:\n", name) : fmt::format("{:<40}; {}\n", fmt::format("{}:", name), note);
  }
  // An instruction, its mnemonic padded so that operands line up.
  void line(std::string_view code, std::string_view note = {}) {
    std::string text(code);
    if (const auto space = text.find(' '); space != std::string::npos && space < 7) text.insert(space, 7 - space, ' ');
    out_ += note.empty() ? fmt::format("        {}\n", text) : fmt::format("        {:<32} ; {}\n", text, note);
  }
  void insn(const isa::Instruction& i, std::string_view note = {}) { line(with_launch_field(i), note); }

  // The disassembly, with the offset of a load from the launch block through the bases
  // register written as the field's symbol: [r30.y + LAUNCH_ORIGIN_AT].
  std::string with_launch_field(const isa::Instruction& i) const {
    std::string text = isa::disassemble(i);
    const bool launch_base = i.src[0].reg == p_.regs.bases && (i.src[0].swizzle & 3) == kBaseLaunch;
    const auto operands = std::span(i.spec->operands).first(static_cast<std::size_t>(i.spec->operand_count));
    if (!launch_base || std::find(operands.begin(), operands.end(), isa::Operand::kMem) == operands.end()) return text;
    for (const spec::isa::AsmSymbol& s : spec::isa::kAsmSymbols) {
      if (s.value != i.imm || !s.name.starts_with("LAUNCH_") || !s.name.ends_with("_AT")) continue;
      const std::size_t open = text.find('['), close = text.find(']');
      const std::size_t base_end = std::min(text.find(' ', open), close);
      return text.substr(0, base_end) + " + " + std::string(s.name) + text.substr(close);
    }
    return text;
  }
  // A branch or call to a label: the disassembly with its target (printed last, as a
  // number) replaced by the label.
  void jump(isa::Instruction i, std::string_view target, std::string_view note = {}) {
    i.imm = 0;
    std::string text = isa::disassemble(i);
    text.resize(text.size() - 1);
    line(text + std::string(target), note);
  }
  std::string fresh(std::string_view stem) { return fmt::format("{}_{}", stem, labels_++); }

  void header() {
    const Machine& m = p_.machine;
    out_ += fmt::format("; rpu_progen seed {}: for {} registers, chunk size {}, call depth {}, {} stack bytes; "
                        "ends in {}\n",
                        p_.seed, m.registers, m.chunk_size, m.call_depth, m.stack_bytes, fault_name(p_.fault));
    out_ += fmt::format("; r{}: pixel (x, y, index, 0); r{}: addresses (own framebuffer pixel, launch block, .data, "
                        "image); r{}.x: loop counter; r0..r{} free\n",
                        p_.regs.pixel, p_.regs.bases, p_.regs.counter, p_.regs.free - 1);
  }

  void data() {
    out_ += "        .data\nvalues:\n";
    for (std::size_t i = 0; i < p_.data.size(); i += 4) {
      std::string words;
      for (std::size_t k = i; k < std::min(i + 4, p_.data.size()); ++k) {
        words += fmt::format("{}{:#010x}", k == i ? "" : ", ", p_.data[k]);
      }
      line(".word " + words);
    }
    out_ += "        .text\n";
  }

  void raygen() {
    const RegisterPlan& r = p_.regs;
    label("raygen");
    comment("prologue: the pixel and the base addresses every statement uses");
    line(fmt::format("rdsr r{}, pixel", r.pixel));
    line(fmt::format("li r{}.y, DEVICE_LAUNCH_BASE", r.bases));
    line(fmt::format("ld1 r{}.x, [r{}.y + LAUNCH_FRAMEBUFFER_AT]", r.bases, r.bases));
    line(fmt::format("imuli r{}.w, r{}.z, FRAMEBUFFER_BYTES_PER_PIXEL", r.bases, r.pixel));
    line(fmt::format("iadd r{}.x, r{}.x, r{}.w", r.bases, r.bases, r.bases), "own framebuffer pixel");
    line(fmt::format("li r{}.z, values", r.bases));
    line(fmt::format("li r{}.w, DEVICE_IMAGE_BASE", r.bases));
    block(p_.raygen);
    line("halt");
  }

  void routine(int index) {
    const Routine& r = p_.routines[static_cast<std::size_t>(index)];
    const int shader_id = static_cast<int>(std::count_if(p_.routines.begin(), p_.routines.begin() + index,
                                                         [](const Routine& x) { return x.shader; }));
    label(r.label, r.shader ? fmt::format("hit shader, id {}, level {}", shader_id, index)
                            : fmt::format("function, level {}", index));
    const isa::Source ra = reg(r.return_register, broadcast(r.return_lane));
    if (r.keeps_return_address) {
      insn(make_instruction(Opcode::kMfra, r.return_register, lane_bit(r.return_lane)), "keep the return address");
      insn(make_instruction(Opcode::kPush, 0, 0, reg(r.return_register)));
    }
    block(r.body);
    if (r.keeps_return_address) {
      insn(make_instruction(Opcode::kPop, r.return_register));
      insn(make_instruction(Opcode::kMtra, 0, 0, ra), "put the return address back");
    }
    line("ret");
  }

  void block(const std::vector<Statement>& statements) {
    for (const Statement& s : statements) statement(s);
  }

  void statement(const Statement& s) {
    switch (s.kind) {
      case StatementKind::kInstruction: insn(s.insns.front(), s.note); break;
      case StatementKind::kGroup:
        if (!s.note.empty()) comment(s.note);
        block(s.body);
        break;
      case StatementKind::kIndexedLoad:
      case StatementKind::kCalli:
      case StatementKind::kReturnAddress:
        if (!s.note.empty()) comment(s.note);
        for (const isa::Instruction& i : s.insns) insn(i);
        break;
      case StatementKind::kIf: if_else(s); break;
      case StatementKind::kLoop: loop(s); break;
      case StatementKind::kCall:
        jump(make_instruction(Opcode::kCall), p_.routines[static_cast<std::size_t>(s.routine)].label, s.note);
        break;
      case StatementKind::kPushPop: {
        const std::size_t pushes = s.insns.size() / 2;
        comment(s.note.empty() ? "push/pop" : s.note);
        for (std::size_t i = 0; i < pushes; ++i) insn(s.insns[i]);
        block(s.body);
        for (std::size_t i = pushes; i < s.insns.size(); ++i) insn(s.insns[i]);
        break;
      }
      case StatementKind::kHalt: line("halt", s.note); break;
      case StatementKind::kFault: fault(s.fault); break;
    }
  }

  void if_else(const Statement& s) {
    const Condition& c = s.condition;
    comment(fmt::format("if {}", c.text));
    for (const isa::Instruction& i : c.setup) insn(i);
    const std::string other = fresh("else"), end = fresh("endif");
    const bool has_other = !s.other.empty();
    jump(make_instruction(c.when_zero ? Opcode::kBnz : Opcode::kBz, 0, 0, reg(c.reg, c.swizzle)),
         has_other ? other : end);
    block(s.body);
    if (has_other) {
      jump(make_instruction(Opcode::kBra), end);
      label(other);
      block(s.other);
    }
    label(end);
  }

  void loop(const Statement& s) {
    const int counter = p_.regs.counter;
    comment(fmt::format("loop of at most {} trip{}: {}", s.trips, s.trips == 1 ? "" : "s", s.note));
    insn(make_instruction(Opcode::kPush, 0, 0, reg(counter)), "keep the enclosing loop's counter");
    for (const isa::Instruction& i : s.insns) insn(i);
    const std::string top = fresh("loop");
    label(top);
    block(s.body);
    counted_loop_end(top);
    insn(make_instruction(Opcode::kPop, counter));
  }

  void counted_loop_end(std::string_view top) {
    const int counter = p_.regs.counter;
    insn(make_instruction(Opcode::kIaddi, counter, lane_bit(0), reg(counter), {}, {}, 0xffffffffu));
    jump(make_instruction(Opcode::kBnz, 0, 0, reg(counter, broadcast(0))), top);
  }

  void fault(const FaultCode& f) {
    comment(fmt::format("fault ({}): {}", fault_name(f.fault), f.text));
    for (const std::uint64_t w : f.before) line(isa::disassemble(w));
    if (f.repeat) {
      insn(make_instruction(Opcode::kLi, p_.regs.counter, lane_bit(0), {}, {}, {}, f.repeat));
      const std::string top = fresh("fault_loop");
      label(top);
      for (const std::uint64_t w : f.repeated) line(isa::disassemble(w));
      counted_loop_end(top);
    }
    for (const std::uint64_t w : f.after) line(isa::disassemble(w));
    if (f.branch_past_end) jump(make_instruction(Opcode::kBra), "code_end");
    if (f.spin) {
      const std::string top = fresh("spin");
      label(top);
      for (const isa::Instruction& i : f.spin_branches) jump(i, top);
      jump(make_instruction(Opcode::kBra), top);
    }
  }

 private:
  const Program& p_;
  std::string out_;
  int labels_ = 0;
};

std::size_t count_statements(const std::vector<Statement>& list) {
  std::size_t n = 0;
  for (const Statement& s : list) n += 1 + count_statements(s.body) + count_statements(s.other);
  return n;
}

std::optional<std::uint32_t> fault_pixel_in(const std::vector<Statement>& list) {
  for (const Statement& s : list) {
    if (s.kind == StatementKind::kFault) return 0;
    if (s.kind == StatementKind::kGroup) {
      if (auto p = fault_pixel_in(s.body)) return p;
    }
    if (s.kind == StatementKind::kIf && s.other.empty()) {
      const auto inner = fault_pixel_in(s.body);
      if (inner && *inner == 0) return s.condition.first_pixel;
    }
  }
  return std::nullopt;
}

}  // namespace

std::uint64_t fault_instructions(const FaultCode& f) {
  return f.before.size() + (f.repeat ? 1 + std::uint64_t{f.repeat} * (f.repeated.size() + 2) : 0) + f.after.size() +
         (f.branch_past_end ? 1 : 0) + (f.spin ? f.spin_branches.size() + 1 : 0);
}

std::string Program::assembly() const {
  Writer w(*this);
  w.header();
  w.data();
  w.raygen();
  for (std::size_t i = 0; i < routines.size(); ++i) w.routine(static_cast<int>(i));
  w.label("code_end", "the pc fault branches here, past the last instruction");
  return std::move(w).text();
}

isa::Firmware Program::firmware() const {
  const std::string name = fmt::format("progen-{}.s", seed);
  const std::string text = assembly();
  return isa::assemble(name, [&](const std::filesystem::path& path) -> std::optional<std::string> {
    if (path == name) return text;
    return std::nullopt;
  });
}

std::vector<std::string> Program::shader_names() const {
  std::vector<std::string> names;
  for (const Routine& r : routines) {
    if (r.shader) names.push_back(r.label.substr(4));  // after "hit_"
  }
  return names;
}


CostModel::CostModel(const Program& p) : routines_(p.routines.size()) {
  for (std::size_t i = 0; i < p.routines.size(); ++i) {
    if (p.routines[i].shader) shader_routine_.push_back(static_cast<int>(i));
  }
  for (std::size_t i = p.routines.size(); i-- > 0;) update(p, static_cast<int>(i));
}

void CostModel::update(const Program& p, int index) {
  const Routine& r = p.routines[static_cast<std::size_t>(index)];
  const Cost body = sequence(r.body);
  const std::uint32_t keeps = r.keeps_return_address ? 1 : 0;
  routines_[static_cast<std::size_t>(index)] = {body.instructions + 1 + 4 * keeps, body.stack + keeps, body.returns};
}

Cost CostModel::sequence(const std::vector<Statement>& list) const {
  Cost total;
  for (const Statement& s : list) {
    const Cost c = statement(s);
    // Every statement leaves both stacks as it found them, so their peaks do not add.
    total.instructions += c.instructions;
    total.stack = std::max(total.stack, c.stack);
    total.returns = std::max(total.returns, c.returns);
  }
  return total;
}

Cost CostModel::statement(const Statement& s) const {
  const auto n = static_cast<std::uint64_t>(s.insns.size());
  switch (s.kind) {
    case StatementKind::kInstruction:
    case StatementKind::kIndexedLoad:
    case StatementKind::kReturnAddress:
      return {n, 0, 0};
    case StatementKind::kHalt: return {1, 0, 0};
    case StatementKind::kGroup: return sequence(s.body);
    case StatementKind::kIf: {
      const Cost then = sequence(s.body), other = sequence(s.other);
      const std::uint64_t setup = s.condition.setup.size() + 1;
      return {setup + std::max(then.instructions + (s.other.empty() ? 0 : 1), other.instructions),
              std::max(then.stack, other.stack), std::max(then.returns, other.returns)};
    }
    case StatementKind::kLoop: {
      // push, the counter's set-up, trips x (body, iaddi, bnz), pop
      const Cost body = sequence(s.body);
      return {2 + n + s.trips * (body.instructions + 2), 1 + body.stack, body.returns};
    }
    case StatementKind::kCall: {
      const Cost r = routine(s.routine);
      return {1 + r.instructions, r.stack, 1 + r.returns};
    }
    case StatementKind::kCalli: {
      Cost worst;
      for (int id = s.shader_lo; id <= s.shader_hi; ++id) {
        const Cost r = routine(shader_routine_[static_cast<std::size_t>(id)]);
        worst = {std::max(worst.instructions, r.instructions), std::max(worst.stack, r.stack),
                 std::max(worst.returns, r.returns)};
      }
      return {n + worst.instructions, worst.stack, 1 + worst.returns};
    }
    case StatementKind::kPushPop: {
      const Cost body = sequence(s.body);
      return {n + body.instructions, static_cast<std::uint32_t>(n / 2) + body.stack, body.returns};
    }
    case StatementKind::kFault: return {fault_instructions(s.fault), 0, 0};
  }
  return {};
}

Cost Program::cost() const {
  Cost c = CostModel(*this).sequence(raygen);
  c.instructions += kPrologueInstructions + 1;  // and the halt
  return c;
}

std::uint64_t Program::watchdog() const {
  if (fault == FaultClass::kWatchdog) return watchdog_limit;
  // A spinning thread faults once it has retired as many branches in a row as the code
  // has instructions: at most that many past its first trip of the loop.
  if (fault == FaultClass::kSpin) return cost().instructions + firmware().code.size() + 1;
  return cost().instructions;
}

std::optional<std::uint32_t> Program::fault_pixel() const {
  if (fault == FaultClass::kNone) return std::nullopt;
  return fault_pixel_in(raygen);
}

std::size_t Program::statement_count() const {
  std::size_t n = count_statements(raygen);
  for (const Routine& r : routines) n += count_statements(r.body);
  return n;
}

}  // namespace rpu::progen
