#include "spu_checker.hpp"

#include <bit>
#include <cmath>

#include <fmt/format.h>

#include "cosim_core.hpp"
#include "isa/instruction.hpp"

namespace rpu::sim {

namespace {

std::string lane_text(std::uint32_t v) {
  return fmt::format("{:08x} ({})", v, std::bit_cast<float>(v));
}

std::string fault_kind_name(std::uint32_t kind) {
  return kind < spec::isa::kFaults.size() ? std::string(spec::isa::kFaults[kind].name) : fmt::format("kind {}", kind);
}

}  // namespace

std::string SpuChecker::insn_text(std::uint32_t pc) const {
  return pc < setup_.firmware->code.size() ? isa::disassemble(setup_.firmware->code[pc]) : "past the end of the code";
}

SpuChecker::SpuChecker(const SpuCheckerSetup& setup, functional::DeviceMemory& memory)
    : setup_(setup),
      core_(*setup.firmware, memory, *setup.tracer, setup.format, setup.core),
      chunks_(setup.threads_per_core / static_cast<std::uint32_t>(setup.core.chunk_size)),
      threads_(setup.threads_per_core),
      map_(setup.cores, setup.threads_per_core, static_cast<std::uint32_t>(setup.core.chunk_size), setup.pixels) {}

std::string SpuChecker::where(std::uint32_t thread) const {
  const auto c = thread / static_cast<std::uint32_t>(setup_.core.chunk_size);
  const auto l = thread % static_cast<std::uint32_t>(setup_.core.chunk_size);
  std::string text = fmt::format("core {}, thread {} (chunk {}, lane {})", setup_.core_id, thread, c, l);
  if (c < chunks_.size() && chunks_[c].started) {
    const auto& ts = chunks_[c].chunk.threads();
    if (l < ts.size()) {
      const std::uint32_t p = ts[l].lane.pixel;
      text += fmt::format(", pixel {} ({}, {})", p, p % setup_.width, p / setup_.width);
    }
  }
  return text;
}

void SpuChecker::fail(std::uint64_t cycle, std::uint32_t thread, const std::string& what) const {
  throw CosimFailure(fmt::format("lockstep mismatch at cycle {}, {}: {}", cycle, where(thread), what));
}

void SpuChecker::start_round(std::uint32_t c, std::uint64_t cycle) {
  Chunk& ch = chunks_[c];
  const auto size = static_cast<std::uint32_t>(setup_.core.chunk_size);
  const std::int64_t round = ch.round + 1;
  map_.lanes(map_.block(static_cast<std::uint64_t>(round), setup_.core_id, c), lanes_);
  if (lanes_.empty()) {
    fail(cycle, c * size, fmt::format("the RTL issues for chunk {} past its last round ({} rounds of {} pixels)", c,
                                      round, setup_.pixels));
  }
  core_.start(ch.chunk, lanes_, stats_);
  ch.round = round;
  ch.started = true;
  if (setup_.observer) setup_.observer->start_chunk(ch.chunk);
}

void SpuChecker::on_issue(const streams::Issue& r, std::uint64_t cycle) {
  const auto size = static_cast<std::uint32_t>(setup_.core.chunk_size);
  if (r.core != setup_.core_id || r.chunk >= chunks_.size()) {
    throw CosimFailure(fmt::format("issue record at cycle {} names core {} chunk {}: this checker follows core {} "
                                   "({} chunks)",
                                   cycle, r.core, r.chunk, setup_.core_id, chunks_.size()));
  }
  Chunk& ch = chunks_[r.chunk];
  if (!ch.started || ch.chunk.done()) start_round(r.chunk, cycle);
  const std::uint32_t first = r.chunk * size;
  if (ch.chunk.next_pc() != r.pc) {
    fail(cycle, first, fmt::format("chunk {} issues pc {} ({}), the functional model's smallest live pc is {} ({})",
                                   r.chunk, r.pc, insn_text(r.pc), ch.chunk.next_pc(), insn_text(ch.chunk.next_pc())));
  }
  // The lanes standing at the pc; a fault in one stops the later ones within the step.
  std::uint32_t standing = 0;
  for (std::uint32_t l = 0; l < ch.chunk.threads().size(); ++l) {
    const auto& t = ch.chunk.threads()[l];
    if (!t.done && t.pc == r.pc) standing |= 1u << l;
  }
  if (standing != r.lanes) {
    fail(cycle, first, fmt::format("chunk {} at pc {} ({}): the RTL issues lanes {:#x}, the functional model's lanes "
                                   "standing there are {:#x}",
                                   r.chunk, r.pc, insn_text(r.pc), r.lanes, standing));
  }
  const functional::ShaderFault* before = ch.chunk.fault();
  const std::uint32_t fault_pixel_before = before ? before->pixel() : 0xffffffffu;
  if (setup_.observer) setup_.observer->before_step(ch.chunk);
  core_.step(ch.chunk, stats_, &record_);
  if (setup_.observer) setup_.observer->after_step(record_, ch.chunk);
  ++steps_;
  // A lane that faulted this step is the chunk's new first fault; it does not retire.
  const functional::ShaderFault* after = ch.chunk.fault();
  const bool new_fault = after && after->pixel() != fault_pixel_before;
  for (std::uint32_t l = 0; l < size; ++l) {
    if (!(record_.lanes >> l & 1)) continue;
    const std::uint32_t t = first + l;
    const auto& thread = ch.chunk.threads()[l];
    if (new_fault && thread.lane.pixel == after->pixel()) {
      threads_[t].fault = *after;
      continue;
    }
    Expected e;
    e.pc = r.pc;
    e.insn = r.pc < setup_.firmware->code.size() ? setup_.firmware->code[r.pc] : 0;
    for (const functional::MemoryAccess& a : record_.accesses) {
      if (a.lane == l) e.addr = a.address;
    }
    threads_[t].retires.push_back(e);
    // Every executed instruction with a destination writes it (an empty mask too).
    if (core_.instruction(r.pc) && core_.register_use(r.pc).dst >= 0) {
      threads_[t].writes[core_.register_use(r.pc).dst].push_back(r.pc);
    }
  }
  if (new_fault && !first_fault_) first_fault_ = *after;
  if (new_fault && first_fault_ && after->pixel() < first_fault_->pixel()) first_fault_ = *after;
}

void SpuChecker::on_retire(const streams::Retire& r, std::uint64_t cycle) {
  if (r.thread >= threads_.size()) fail(cycle, 0, fmt::format("retire record for thread {}", r.thread));
  Thread& t = threads_[r.thread];
  const std::uint64_t insn = std::uint64_t{r.insn[1]} << 32 | r.insn[0];
  if (t.retires.empty()) {
    fail(cycle, r.thread, fmt::format("the RTL retires pc {} ({}), the functional model has no instruction of this "
                                      "thread executed and not yet retired",
                                      r.pc, isa::disassemble(insn)));
  }
  const Expected e = t.retires.front();
  t.retires.pop_front();
  if (e.pc != r.pc || e.insn != insn || e.addr != r.addr) {
    fail(cycle, r.thread, fmt::format("retire: expected pc {} ({}) address {:#010x}, the RTL retires pc {} ({}) "
                                      "address {:#010x}",
                                      e.pc, isa::disassemble(e.insn), e.addr, r.pc, isa::disassemble(insn), r.addr));
  }
  ++retired_;
}

void SpuChecker::on_writeback(const streams::Writeback& r, std::uint64_t cycle) {
  if (r.thread >= threads_.size()) fail(cycle, 0, fmt::format("writeback for thread {}", r.thread));
  Thread& t = threads_[r.thread];
  const auto it = t.writes.find(static_cast<int>(r.dst));
  if (it == t.writes.end()) {
    fail(cycle, r.thread, fmt::format("the RTL writes r{} (mask {:#x}); no executed instruction of this thread owes "
                                      "that write",
                                      r.dst, r.wmask));
  }
  const std::uint32_t pc = it->second.front();
  it->second.pop_front();
  if (it->second.empty()) t.writes.erase(it);
  const auto size = static_cast<std::uint32_t>(setup_.core.chunk_size);
  const auto& thread = chunks_[r.thread / size].chunk.threads()[r.thread % size];
  const auto& reg = thread.regs[r.dst];
  std::string lanes;
  bool differs = false;
  for (int l = 0; l < 4; ++l) {
    if (!(r.wmask >> l & 1)) continue;
    const bool d = reg[static_cast<std::size_t>(l)] != r.value[static_cast<std::size_t>(l)];
    differs |= d;
    lanes += fmt::format("\n    r{}.{}: expected {}, got {}{}", r.dst, "xyzw"[l], lane_text(reg[static_cast<std::size_t>(l)]),
                         lane_text(r.value[static_cast<std::size_t>(l)]), d ? "  <- differs" : "");
  }
  if (differs) {
    fail(cycle, r.thread, fmt::format("writeback of r{} by pc {} ({}) differs{}", r.dst, pc, insn_text(pc), lanes));
  }
}

void SpuChecker::on_fault(const streams::Fault& r, std::uint64_t cycle) {
  if (r.thread >= threads_.size()) fail(cycle, 0, fmt::format("fault record for thread {}", r.thread));
  Thread& t = threads_[r.thread];
  if (!t.fault) {
    fail(cycle, r.thread, fmt::format("the RTL reports a {} fault at pc {} address {:#010x}; the functional model has "
                                      "no fault in this thread here",
                                      fault_kind_name(r.kind), r.pc, r.addr));
  }
  const functional::ShaderFault& f = *t.fault;
  if (static_cast<std::uint32_t>(f.kind()) != r.kind || f.pc() != r.pc || f.address() != r.addr ||
      f.pixel() != r.pixel) {
    fail(cycle, r.thread, fmt::format("fault: expected {} at pc {} address {:#010x} pixel {}, the RTL reports {} at "
                                      "pc {} address {:#010x} pixel {}\n  functional: {}",
                                      fault_kind_name(static_cast<std::uint32_t>(f.kind())), f.pc(), f.address(),
                                      f.pixel(), fault_kind_name(r.kind), r.pc, r.addr, r.pixel, f.what()));
  }
  t.fault.reset();
}

void SpuChecker::finish(std::optional<std::uint32_t> stop_pixel) const {
  const auto size = static_cast<std::uint32_t>(setup_.core.chunk_size);
  for (std::uint32_t t = 0; t < threads_.size(); ++t) {
    if (!threads_[t].retires.empty()) {
      const Expected& e = threads_[t].retires.front();
      fail(0, t, fmt::format("at the end, {} executed instruction(s) never retired by the RTL, the first pc {} ({})",
                             threads_[t].retires.size(), e.pc, isa::disassemble(e.insn)));
    }
    if (!threads_[t].writes.empty()) {
      const auto& [reg, pcs] = *threads_[t].writes.begin();
      fail(0, t, fmt::format("at the end, the RTL never wrote r{} for pc {} ({})", reg, pcs.front(),
                             insn_text(pcs.front())));
    }
    if (threads_[t].fault) fail(0, t, std::string("at the end, the RTL never reported: ") + threads_[t].fault->what());
  }
  for (std::uint32_t c = 0; c < chunks_.size(); ++c) {
    const Chunk& ch = chunks_[c];
    if (ch.started && !ch.chunk.done()) {
      fail(0, c * size, fmt::format("at the end, chunk {} still has live lanes at pc {} in the functional model", c,
                                    ch.chunk.next_pc()));
    }
    // The round after the last one run must not have been due.
    const std::int64_t next = ch.round + 1;
    const std::uint64_t p = map_.first_pixel(map_.block(static_cast<std::uint64_t>(next), setup_.core_id, c));
    if (p < setup_.pixels && !(stop_pixel && p > *stop_pixel)) {
      fail(0, c * size, fmt::format("at the end, chunk {} never ran round {} (pixel {} onwards)", c, next, p));
    }
  }
}

const functional::ShaderFault* SpuChecker::first_fault() const { return first_fault_ ? &*first_fault_ : nullptr; }

}  // namespace rpu::sim
