// shrink(): delta debugging over a program's structure (docs/random-programs.md
// "Shrinking"). Every edit is one the generator's rules allow (a statement removed, a
// region's body put in its place, a call inlined, operands made plain), so every
// candidate is legal and terminates.
#include <algorithm>
#include <utility>

#include "progen/make_instruction.hpp"
#include "progen/progen.hpp"

namespace rpu::progen {

namespace {

using Predicate = std::function<bool(const Program&)>;

// A statement list: raygen's (root -1) or a routine's body, then (statement index,
// 0 for its body or 1 for its else part) down to the list.
struct ListPath {
  int root = -1;
  std::vector<std::pair<std::size_t, int>> steps;
};

// For a Program or a const Program.
template <class P>
auto list_at(P& p, const ListPath& path) -> decltype((p.raygen)) {
  auto* list = path.root < 0 ? &p.raygen : &p.routines[static_cast<std::size_t>(path.root)].body;
  for (const auto& [index, part] : path.steps) {
    auto& s = (*list)[index];
    list = part == 0 ? &s.body : &s.other;
  }
  return *list;
}

void collect_lists(const std::vector<Statement>& list, ListPath& path, std::vector<ListPath>& out) {
  if (list.empty()) return;
  out.push_back(path);
  for (std::size_t i = 0; i < list.size(); ++i) {
    for (int part = 0; part < 2; ++part) {
      path.steps.emplace_back(i, part);
      collect_lists(part == 0 ? list[i].body : list[i].other, path, out);
      path.steps.pop_back();
    }
  }
}

// Every non-empty statement list, raygen's first, each before the lists inside it.
std::vector<ListPath> all_lists(const Program& p) {
  std::vector<ListPath> out;
  for (int root = -1; root < static_cast<int>(p.routines.size()); ++root) {
    ListPath path{root, {}};
    collect_lists(root < 0 ? p.raygen : p.routines[static_cast<std::size_t>(root)].body, path, out);
  }
  return out;
}

// Removes chunks of the list, halving their size down to single statements (ddmin's
// complement tests).
bool reduce_list(Program& p, const ListPath& path, const Predicate& still_fails) {
  bool changed = false;
  for (std::size_t chunk = list_at(p, path).size(); chunk > 0; chunk /= 2) {
    for (std::size_t i = 0; i < list_at(p, path).size();) {
      Program candidate = p;
      std::vector<Statement>& list = list_at(candidate, path);
      list.erase(list.begin() + static_cast<std::ptrdiff_t>(i),
                 list.begin() + static_cast<std::ptrdiff_t>(std::min(i + chunk, list.size())));
      if (still_fails(candidate)) {
        p = std::move(candidate);
        changed = true;
      } else {
        i += chunk;
      }
    }
  }
  return changed;
}

// Without kReturnAddress statements: what a routine's body becomes when it is inlined,
// where no return address of its own is on the return stack.
std::vector<Statement> inlined(std::vector<Statement> body) {
  std::erase_if(body, [](const Statement& s) { return s.kind == StatementKind::kReturnAddress; });
  for (Statement& s : body) {
    s.body = inlined(std::move(s.body));
    s.other = inlined(std::move(s.other));
  }
  return body;
}

int shader_routine(const Program& p, int shader_id) {
  int id = 0;
  for (std::size_t i = 0; i < p.routines.size(); ++i) {
    if (p.routines[i].shader && id++ == shader_id) return static_cast<int>(i);
  }
  return -1;
}

// The statements that may stand in the place of `s`, simplest first.
std::vector<std::vector<Statement>> replacements(const Program& p, const Statement& s) {
  std::vector<std::vector<Statement>> out;
  switch (s.kind) {
    case StatementKind::kGroup:
    case StatementKind::kLoop:
    case StatementKind::kPushPop: out.push_back(s.body); break;
    case StatementKind::kIf:
      out.push_back(s.body);
      if (!s.other.empty()) out.push_back(s.other);
      break;
    case StatementKind::kCall:
      out.push_back(inlined(p.routines[static_cast<std::size_t>(s.routine)].body));
      break;
    case StatementKind::kCalli: {
      Statement call;
      call.kind = StatementKind::kCall;
      call.routine = shader_routine(p, s.shader_lo);
      call.note = s.note;
      out.push_back({call});
      break;
    }
    default: break;
  }
  if (s.kind == StatementKind::kLoop && s.trips > 1) {
    Statement once = s;
    once.trips = 1;
    once.insns = {make_instruction(isa::Opcode::kLi, p.regs.counter, lane_bit(0), {}, {}, {}, 1)};
    once.note = "1 trip";
    out.push_back({once});
  }
  if (s.kind == StatementKind::kInstruction && is_pure_compute(*s.insns.front().spec)) {
    Statement plain = s;
    isa::Instruction& i = plain.insns.front();
    for (isa::Source& src : i.src) src = reg(src.reg);
    i.wmask = isa::kAllLanes;
    if (isa::encode(i) != isa::encode(s.insns.front())) out.push_back({plain});
    if (i.imm != 0) {
      plain.insns.front().imm = 0;
      out.push_back({plain});
    }
  }
  return out;
}

struct StatementPath {
  ListPath list;
  std::size_t index;
};

void collect_statements(const Program& p, std::vector<StatementPath>& out) {
  for (const ListPath& path : all_lists(p)) {
    for (std::size_t i = 0; i < list_at(p, path).size(); ++i) out.push_back({path, i});
  }
}

bool replace_statements(Program& p, const Predicate& still_fails) {
  bool changed = false;
  for (std::size_t k = 0;; ++k) {
    std::vector<StatementPath> paths;
    collect_statements(p, paths);
    if (k >= paths.size()) break;
    const StatementPath& at = paths[k];
    const Statement original = list_at(p, at.list)[at.index];
    for (std::vector<Statement>& r : replacements(p, original)) {
      Program candidate = p;
      std::vector<Statement>& list = list_at(candidate, at.list);
      list.erase(list.begin() + static_cast<std::ptrdiff_t>(at.index));
      list.insert(list.begin() + static_cast<std::ptrdiff_t>(at.index), std::make_move_iterator(r.begin()),
                  std::make_move_iterator(r.end()));
      if (still_fails(candidate)) {
        p = std::move(candidate);
        changed = true;
        break;
      }
    }
  }
  return changed;
}

// Routines raygen reaches through call and calli (and, for a call-depth fault that ends
// in calli, shader 0).
std::vector<bool> reachable(const Program& p) {
  std::vector<bool> seen(p.routines.size(), false);
  std::vector<int> work;
  const auto reach = [&](int r) {
    if (r >= 0 && !seen[static_cast<std::size_t>(r)]) {
      seen[static_cast<std::size_t>(r)] = true;
      work.push_back(r);
    }
  };
  const auto scan = [&](const std::vector<Statement>& list, const auto& self) -> void {
    for (const Statement& s : list) {
      if (s.kind == StatementKind::kCall) reach(s.routine);
      if (s.kind == StatementKind::kCalli) {
        for (int id = s.shader_lo; id <= s.shader_hi; ++id) reach(shader_routine(p, id));
      }
      if (s.kind == StatementKind::kFault) {
        for (const std::uint64_t w : s.fault.after) {
          const auto i = isa::decode(w);
          if (i && i->opcode() == isa::Opcode::kCalli) reach(shader_routine(p, 0));
        }
      }
      self(s.body, self);
      self(s.other, self);
    }
  };
  scan(p.raygen, scan);
  while (!work.empty()) {
    const int r = work.back();
    work.pop_back();
    scan(p.routines[static_cast<std::size_t>(r)].body, scan);
  }
  return seen;
}

void renumber_calls(std::vector<Statement>& list, const std::vector<int>& new_index) {
  for (Statement& s : list) {
    if (s.kind == StatementKind::kCall) s.routine = new_index[static_cast<std::size_t>(s.routine)];
    renumber_calls(s.body, new_index);
    renumber_calls(s.other, new_index);
  }
}

// Functions nothing reaches go; a hit shader nothing reaches keeps its label (the shader
// ids of the others stay) with an empty body.
Program without_unreachable_routines(const Program& p, const std::vector<bool>& seen) {
  Program out = p;
  out.routines.clear();
  std::vector<int> new_index(p.routines.size(), -1);
  for (std::size_t i = 0; i < p.routines.size(); ++i) {
    const Routine& r = p.routines[i];
    if (!seen[i] && !r.shader) continue;
    new_index[i] = static_cast<int>(out.routines.size());
    out.routines.push_back(r);
    if (!seen[i]) {
      out.routines.back().body.clear();
      out.routines.back().keeps_return_address = false;
    }
  }
  renumber_calls(out.raygen, new_index);
  for (Routine& r : out.routines) renumber_calls(r.body, new_index);
  return out;
}

bool simplify_routines(Program& p, const Predicate& still_fails) {
  bool changed = false;
  const std::vector<bool> seen = reachable(p);
  bool dead = false;
  for (std::size_t i = 0; i < p.routines.size(); ++i) {
    const Routine& r = p.routines[i];
    dead |= !seen[i] && (!r.shader || !r.body.empty() || r.keeps_return_address);
  }
  if (dead) {
    Program candidate = without_unreachable_routines(p, seen);
    if (still_fails(candidate)) {
      p = std::move(candidate);
      changed = true;
    }
  }
  for (std::size_t i = 0; i < p.routines.size(); ++i) {
    if (!p.routines[i].keeps_return_address) continue;
    Program candidate = p;
    candidate.routines[i].keeps_return_address = false;
    if (still_fails(candidate)) {
      p = std::move(candidate);
      changed = true;
    }
  }
  return changed;
}

}  // namespace

Program shrink(const Program& program, const std::function<bool(const Program&)>& still_fails) {
  Program p = program;
  for (bool changed = true; changed;) {
    changed = simplify_routines(p, still_fails);
    for (std::size_t k = 0;; ++k) {
      const std::vector<ListPath> lists = all_lists(p);
      if (k >= lists.size()) break;
      changed |= reduce_list(p, lists[k], still_fails);
    }
    changed |= replace_statements(p, still_fails);
  }
  return p;
}

}  // namespace rpu::progen
