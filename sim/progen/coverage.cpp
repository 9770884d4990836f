#include "progen/coverage.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include <fmt/format.h>

#include "progen/make_instruction.hpp"

namespace rpu::progen {

namespace si = spec::isa;
namespace mm = spec::memory;
using isa::Opcode;
using isa::Operand;

namespace {

constexpr std::array<std::string_view, 3> kSourceNames{"a", "b", "c"};
constexpr std::array<std::string_view, 4> kSwizzleKinds{"identity", "broadcast", "permutation", "other"};
constexpr std::array<std::string_view, 4> kSegments{"image", "launch block", ".data", "own framebuffer pixel"};

int swizzle_kind(std::uint8_t s) {
  if (s == isa::kIdentitySwizzle) return 0;
  const int x = s & 3, y = s >> 2 & 3, z = s >> 4 & 3, w = s >> 6 & 3;
  if (x == y && y == z && z == w) return 1;
  if ((1 << x | 1 << y | 1 << z | 1 << w) == 0xf) return 2;
  return 3;
}

// The segment of a device address (docs/shader-core.md "Memory"), or -1.
int segment(std::uint32_t address) {
  if (address >= mm::kDeviceFramebufferBase) return 3;
  if (address >= mm::kDeviceStackBase) return -1;
  if (address >= mm::kDeviceDataBase) return 2;
  if (address >= mm::kDeviceLaunchBase) return 1;
  return 0;
}

int load_index(Opcode op) {
  const auto* it = std::find(kLoads.begin(), kLoads.end(), op);
  return it == kLoads.end() ? -1 : static_cast<int>(it - kLoads.begin());
}

std::string mask_name(int m) {
  if (m == 0) return ".none";
  std::string s = ".";
  for (int i = 0; i < 4; ++i) {
    if (m >> i & 1) s += "xyzw"[i];
  }
  return s;
}

// Which source field an operand reads: a memory operand's base is source a.
int source_of(Operand o) {
  switch (o) {
    case Operand::kA:
    case Operand::kMem: return 0;
    case Operand::kB: return 1;
    case Operand::kC: return 2;
    default: return -1;
  }
}

}  // namespace

int Coverage::add(std::string_view group, std::string name) {
  items_.push_back({group, std::move(name), 0});
  return static_cast<int>(items_.size() - 1);
}

Coverage::Coverage() {
  instruction_.fill(-1);
  for (const si::InsnSpec& s : si::kInsns) {
    instruction_[static_cast<std::size_t>(s.opcode)] = add("instruction", std::string(s.mnemonic));
  }
  for (std::size_t k = 0; k < 3; ++k) {
    modifier_[k][0] = add("source modifier", fmt::format("-{}", kSourceNames[k]));
    // The encoding has no abs bit for source c (spec/isa.toml [encoding]).
    modifier_[k][1] = k < 2 ? add("source modifier", fmt::format("|{}|", kSourceNames[k])) : -1;
    modifier_[k][2] = k < 2 ? add("source modifier", fmt::format("-|{}|", kSourceNames[k])) : -1;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t kind = 0; kind < 4; ++kind) {
      swizzle_[k][kind] = add("swizzle", fmt::format("{} {}", kSourceNames[k], kSwizzleKinds[kind]));
    }
  }
  for (int m = 0; m < 16; ++m) mask_[static_cast<std::size_t>(m)] = add("write mask", mask_name(m));
  for (const si::SpecialSpec& s : si::kSpecials) {
    const auto index = static_cast<std::size_t>(s.index);
    if (index >= special_.size()) special_.resize(index + 1, -1);
    special_[index] = add("special register", std::string(s.name));
  }
  for (std::size_t op = 0; op < 4; ++op) {
    for (std::size_t seg = 0; seg < 4; ++seg) {
      load_[op][seg] = add("load", fmt::format("{} from {}", isa::find_insn(kLoads[op])->mnemonic, kSegments[seg]));
    }
  }
  store_[0] = add("store", "st to the own framebuffer pixel");
  store_[1] = add("store", "st1 to the own framebuffer pixel");
  divergent_ = add("control", "divergent step (some live lanes masked off)");
  reconverged_ = add("control", "reconvergence (every live lane issues again)");
  branch_split_ = add("control", "branch taken by some lanes only");
  backward_ = add("control", "backward branch taken (a loop)");
  nested_call_ = add("control", "call or calli at return-stack depth >= 2");
  calli_split_ = add("control", "calli to different routines in one step");
  early_halt_ = add("control", "halt while other lanes run on");
  ray_[0] = add("ray", "trace hit");
  ray_[1] = add("ray", "trace miss");
  ray_[2] = add("ray", "tracea hit");
  ray_[3] = add("ray", "tracea miss");
  fault_.fill(-1);
  for (const FaultClassInfo& f : kFaultClasses) {
    fault_[static_cast<std::size_t>(f.fault)] = add("fault", std::string(f.name));
  }
}

void Coverage::start_chunk(const functional::ShaderCore::Chunk&) { diverged_ = false; }

void Coverage::before_step(const functional::ShaderCore::Chunk& chunk) {
  live_ = 0;
  const auto& threads = chunk.threads();
  for (std::size_t l = 0; l < threads.size(); ++l) {
    if (!threads[l].done) live_ |= 1u << l;
  }
}

void Coverage::after_step(const functional::StepRecord& record, const functional::ShaderCore::Chunk& chunk) {
  const isa::Instruction* insn = record.insn;
  if (!insn) return;  // an illegal instruction: the run's fault counts it
  const auto& threads = chunk.threads();
  const std::uint32_t lanes = record.lanes;
  const si::InsnSpec& spec = *insn->spec;
  const Opcode op = spec.opcode;
  bump(instruction_[static_cast<std::size_t>(op)], static_cast<std::uint64_t>(std::popcount(lanes)));

  for (int k = 0; k < spec.operand_count; ++k) {
    const Operand o = spec.operands[static_cast<std::size_t>(k)];
    if (o == Operand::kD) bump(mask_[insn->wmask]);
    const int s = source_of(o);
    if (s < 0) continue;
    const isa::Source& src = insn->src[static_cast<std::size_t>(s)];
    bump(swizzle_[static_cast<std::size_t>(s)][static_cast<std::size_t>(swizzle_kind(src.swizzle))]);
    if (src.neg || src.abs) bump(modifier_[static_cast<std::size_t>(s)][src.neg && src.abs ? 2 : src.abs ? 1 : 0]);
  }

  if (lanes != live_) {
    bump(divergent_);
    diverged_ = true;
  } else if (diverged_ && std::popcount(live_) >= 2) {
    bump(reconverged_);
    diverged_ = false;
  }

  // The executing lanes in lane order, and their state after the step.
  std::vector<const functional::ShaderCore::Thread*> ran;
  for (std::size_t l = 0; l < threads.size(); ++l) {
    if (lanes >> l & 1) ran.push_back(&threads[l]);
  }
  switch (op) {
    case Opcode::kBz:
    case Opcode::kBnz:
    case Opcode::kBra: {
      bool taken = false, fell_through = false, backward = false;
      for (const auto* t : ran) {
        if (t->done) continue;
        (t->pc == record.pc + 1 ? fell_through : taken) = true;
        backward |= t->pc < record.pc;
      }
      if (taken && fell_through) bump(branch_split_);
      if (backward) bump(backward_);
      break;
    }
    case Opcode::kCall:
    case Opcode::kCalli: {
      bool nested = false, split = false;
      for (const auto* t : ran) {
        if (t->done) continue;
        nested |= t->returns.size() >= 2;
        split |= t->pc != ran.front()->pc;
      }
      if (nested) bump(nested_call_);
      if (op == Opcode::kCalli && split) bump(calli_split_);
      break;
    }
    case Opcode::kHalt:
      if (lanes != live_) bump(early_halt_);
      break;
    case Opcode::kTrace:
    case Opcode::kTracea: {
      // The hit record: t = +inf and primitive 0xffffffff mean a miss; the write mask
      // says which of them the register kept.
      const std::size_t base = op == Opcode::kTrace ? 0 : 2;
      for (const auto* t : ran) {
        const auto& d = t->regs[insn->dst];
        if (insn->wmask & 1) {
          bump(ray_[base + (std::isinf(std::bit_cast<float>(d[0])) ? 1 : 0)]);
        } else if (insn->wmask & 8) {
          bump(ray_[base + (d[3] == 0xffffffffu ? 1 : 0)]);
        }
      }
      break;
    }
    case Opcode::kRdsr:
      if (insn->imm < special_.size() && special_[insn->imm] >= 0) bump(special_[insn->imm]);
      break;
    case Opcode::kSt:
    case Opcode::kSt1:
    case Opcode::kLd:
    case Opcode::kLdf:
    case Opcode::kLd1:
    case Opcode::kLd1f:
      // One access per executing lane, in lane order; a lane done after a load or store
      // faulted in it, and its access does not count.
      for (std::size_t i = 0; i < ran.size() && i < record.accesses.size(); ++i) {
        if (ran[i]->done) continue;
        const int seg = segment(record.accesses[i].address);
        if (seg < 0) continue;
        if (op == Opcode::kSt || op == Opcode::kSt1) {
          bump(store_[op == Opcode::kSt ? 0 : 1]);
        } else {
          bump(load_[static_cast<std::size_t>(load_index(op))][static_cast<std::size_t>(seg)]);
        }
      }
      break;
    default: break;
  }
}

void Coverage::add_outcome(const Outcome& outcome) {
  ++programs_;
  if (!outcome.fault) {
    ++halted_;
    return;
  }
  ++faulted_;
  if (const auto f = classify_fault_message(*outcome.fault)) {
    bump(fault_[static_cast<std::size_t>(*f)]);
  } else {
    ++unclassified_;
  }
}

Coverage& Coverage::operator+=(const Coverage& o) {
  for (std::size_t i = 0; i < items_.size(); ++i) items_[i].count += o.items_[i].count;
  programs_ += o.programs_;
  halted_ += o.halted_;
  faulted_ += o.faulted_;
  unclassified_ += o.unclassified_;
  return *this;
}

std::uint64_t Coverage::count(std::string_view group, std::string_view name) const {
  for (const Item& i : items_) {
    if (i.group == group && i.name == name) return i.count;
  }
  return 0;
}

std::vector<std::string> Coverage::missing(bool faults) const {
  std::vector<std::string> out;
  for (const Item& i : items_) {
    if (i.count == 0 && (faults || i.group != "fault")) out.push_back(fmt::format("{}: {}", i.group, i.name));
  }
  return out;
}

std::string Coverage::report(bool faults) const {
  std::string out = fmt::format("coverage of {} programs: {} halted, {} faulted{}\n", programs_, halted_, faulted_,
                                unclassified_ ? fmt::format(" ({} with a fault message of no class)", unclassified_)
                                              : std::string());
  out += fmt::format("{:<18} {:<46} {:>12}\n", "group", "item", "count");
  std::size_t missing = 0, counted = 0;
  for (const Item& i : items_) {
    if (!faults && i.group == "fault") continue;
    ++counted;
    const bool none = i.count == 0;
    missing += none ? 1 : 0;
    out += fmt::format("{:<18} {:<46} {:>12}{}\n", i.group, i.name, i.count, none ? "  MISSING" : "");
  }
  out += fmt::format("{} of {} items covered{}\n", counted - missing, counted,
                     missing ? fmt::format(", {} missing", missing) : std::string());
  return out;
}

}  // namespace rpu::progen
