#include "cc/regalloc.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu::cc {

namespace {

// Values pushed at most before a function is refused: each spill frees lanes at one
// point, so this bounds the work on a function that cannot fit.
constexpr int kMaxSpills = 256;
// Choices looked at for one spill (values, points, steps of a span), so that a function with
// hundreds of values live compiles in bounded time (or is refused in it).
constexpr std::size_t kMaxTries = 16;
constexpr std::size_t kMaxGrowth = 512;

// A set of vregs as bits.
class Bits {
 public:
  explicit Bits(std::size_t n = 0) : words_((n + 63) / 64) {}
  void set(int i) { words_[static_cast<std::size_t>(i) / 64] |= 1ull << (i % 64); }
  void reset(int i) { words_[static_cast<std::size_t>(i) / 64] &= ~(1ull << (i % 64)); }
  bool test(int i) const { return (words_[static_cast<std::size_t>(i) / 64] >> (i % 64)) & 1u; }
  bool merge(const Bits& o) {
    bool changed = false;
    for (std::size_t k = 0; k < words_.size(); ++k) {
      const std::uint64_t w = words_[k] | o.words_[k];
      changed |= w != words_[k];
      words_[k] = w;
    }
    return changed;
  }
  template <class F>
  void for_each(F f) const {
    for (std::size_t k = 0; k < words_.size(); ++k) {
      for (std::uint64_t w = words_[k]; w; w &= w - 1) f(static_cast<int>(k * 64 + static_cast<std::size_t>(__builtin_ctzll(w))));
    }
  }
  bool operator==(const Bits&) const = default;

 private:
  std::vector<std::uint64_t> words_;
};

bool partial(const MInst& i, const MFunction& f) {
  if (i.dst < 0 || i.dst_comps == 0) return false;
  const int w = f.vregs[static_cast<std::size_t>(i.dst)].width;
  return i.dst_comps != (1u << w) - 1;
}

void uses_of(const MInst& i, const MFunction& f, std::vector<int>& out) {
  out.clear();
  for (const Src& s : i.srcs) out.push_back(s.v);
  for (int u : i.uses) out.push_back(u);
  if (partial(i, f) && !i.fresh) out.push_back(i.dst);
}

void defs_of(const MInst& i, std::vector<int>& out) {
  out.clear();
  if (i.dst >= 0) out.push_back(i.dst);
  for (int d : i.defs) out.push_back(d);
}

bool falls_through(const MInst& m) {
  return m.kind != Kind::kBranch && m.kind != Kind::kRet && m.kind != Kind::kHalt && m.kind != Kind::kTrap;
}

// The control flow between instructions: where a branch goes, and each instruction's
// successors and predecessors.
struct Cfg {
  static constexpr std::size_t kNone = ~std::size_t{0};
  std::vector<std::size_t> target;  // a branch's label, else kNone
  std::vector<std::vector<std::size_t>> succ, preds;
};

Cfg cfg_of(const MFunction& f) {
  const std::size_t n = f.code.size();
  std::unordered_map<std::string, std::size_t> labels;
  for (std::size_t i = 0; i < n; ++i) {
    if (f.code[i].kind == Kind::kLabel) labels[f.code[i].label] = i;
  }
  Cfg c;
  c.target.assign(n, Cfg::kNone);
  c.succ.resize(n);
  c.preds.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MInst& m = f.code[i];
    if (m.kind == Kind::kBranch || m.kind == Kind::kCondBranch) {
      const auto it = labels.find(m.imm.label);
      if (it == labels.end()) throw Error(fmt::format("{}: internal error: no label {}", f.name, m.imm.label));
      c.target[i] = it->second;
      c.succ[i].push_back(it->second);
    }
    if (falls_through(m) && i + 1 < n) c.succ[i].push_back(i + 1);
    for (const std::size_t s : c.succ[i]) c.preds[s].push_back(i);
  }
  return c;
}

struct Liveness {
  std::vector<Bits> live_in, live_out;
  std::vector<std::vector<int>> uses, defs;
};

// Liveness by data flow, backwards to a fixed point.
Liveness liveness(const MFunction& f) {
  const std::size_t n = f.code.size(), nv = f.vregs.size();
  const std::vector<std::vector<std::size_t>> succ = cfg_of(f).succ;
  Liveness l;
  l.live_in.assign(n, Bits(nv));
  l.live_out.assign(n, Bits(nv));
  l.uses.resize(n);
  l.defs.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    uses_of(f.code[i], f, l.uses[i]);
    defs_of(f.code[i], l.defs[i]);
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = n; k-- > 0;) {
      Bits out(nv);
      for (std::size_t s : succ[k]) out.merge(l.live_in[s]);
      Bits in = out;
      for (int d : l.defs[k]) in.reset(d);
      for (int u : l.uses[k]) in.set(u);
      if (!(in == l.live_in[k]) || !(out == l.live_out[k])) {
        changed = true;
        l.live_in[k] = std::move(in);
        l.live_out[k] = std::move(out);
      }
    }
  }
  return l;
}

// What is live at a point: 2i = instruction i reads, 2i + 1 = it writes.
Bits live_at(const Liveness& l, int point) {
  const auto i = static_cast<std::size_t>(point / 2);
  if (point % 2 == 0) return l.live_in[i];
  Bits written = l.live_out[i];
  for (int d : l.defs[i]) written.set(d);
  return written;
}

// Live segments over points. Two vregs may share a lane when no point has both live (a
// def always takes its write point).
std::vector<std::vector<std::pair<int, int>>> segments_of(const MFunction& f, const Liveness& l) {
  std::vector<std::vector<std::pair<int, int>>> segments(f.vregs.size());
  for (int p = 0; p < 2 * static_cast<int>(f.code.size()); ++p) {
    live_at(l, p).for_each([&](int v) {
      auto& segs = segments[static_cast<std::size_t>(v)];
      if (!segs.empty() && segs.back().second >= p - 1) {
        segs.back().second = p;
      } else {
        segs.push_back({p, p});
      }
    });
  }
  return segments;
}

// Per machine lane (register x 4 + lane), the points taken: segment start -> end.
using LaneBusy = std::vector<std::map<int, int>>;

bool overlaps(const std::map<int, int>& busy, int s, int e) {
  auto it = busy.upper_bound(e);  // the first segment starting after e
  if (it == busy.begin()) return false;
  --it;                           // the last segment starting at or before e
  return it->second >= s;
}

// Every vreg in lanes of one register, fixed ones first, the rest by start point (with
// `vectors_first`, the vectors before the scalars, which then fill the lanes vectors
// leave); -1 and the allocation, or the vreg that did not fit (and the lanes taken).
int place(const MFunction& f, const std::vector<std::vector<std::pair<int, int>>>& segments, int registers,
          bool vectors_first, Allocation& a, LaneBusy& lane_busy) {
  const std::size_t nv = f.vregs.size();
  std::vector<int> start(nv, -1);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!segments[v].empty()) start[v] = segments[v].front().first;
  }
  a.location.assign(nv, {});
  a.registers_used = 0;
  lane_busy.assign(static_cast<std::size_t>(registers) * 4, {});
  const auto free_for = [&](int reg, const std::array<std::uint8_t, 4>& lanes, int width, std::size_t v) {
    for (int j = 0; j < width; ++j) {
      const auto& busy = lane_busy[static_cast<std::size_t>(reg * 4 + lanes[static_cast<std::size_t>(j)])];
      for (const auto& [s, e] : segments[v]) {
        if (overlaps(busy, s, e)) return false;
      }
    }
    return true;
  };
  const auto take = [&](std::size_t v, int reg, const std::array<std::uint8_t, 4>& lanes) {
    a.location[v] = {reg, lanes};
    for (int j = 0; j < f.vregs[v].width; ++j) {
      auto& busy = lane_busy[static_cast<std::size_t>(reg * 4 + lanes[static_cast<std::size_t>(j)])];
      for (const auto& [s, e] : segments[v]) busy[s] = e;
    }
    a.registers_used = std::max(a.registers_used, reg + 1);
  };
  // Fixed vregs first: the calling convention's registers.
  for (std::size_t v = 0; v < nv; ++v) {
    const VReg& r = f.vregs[v];
    if (r.fixed < 0 || start[v] < 0) continue;
    if (r.fixed >= registers) {
      throw Error(fmt::format("{}: the calling convention needs register r{}; the firmware may use {}", f.name,
                              r.fixed, registers));
    }
    std::array<std::uint8_t, 4> lanes{0, 1, 2, 3};
    if (r.width == 1) lanes[0] = static_cast<std::uint8_t>(r.fixed_lane);
    if (!free_for(r.fixed, lanes, r.width, v)) {
      throw Error(fmt::format("{}: internal error: two values pinned to r{} overlap", f.name, r.fixed));
    }
    take(v, r.fixed, lanes);
  }
  // The rest by start point. A vreg tries the places of the vregs it is copied from or
  // to first (phi copies, the ABI's registers): sharing one makes the mov vanish.
  std::vector<std::vector<int>> partners(nv);
  for (const MInst& m : f.code) {
    if (m.kind == Kind::kOp && m.op == Opcode::kMov && m.dst >= 0 && m.srcs.size() == 1 && !m.srcs[0].neg &&
        !m.srcs[0].abs && m.srcs[0].n == f.vregs[static_cast<std::size_t>(m.dst)].width &&
        f.vregs[static_cast<std::size_t>(m.srcs[0].v)].width == m.srcs[0].n &&
        (m.dst_comps == 0 || m.dst_comps == (1u << m.srcs[0].n) - 1) &&
        m.srcs[0].comp == std::array<std::uint8_t, 4>{0, 1, 2, 3}) {
      partners[static_cast<std::size_t>(m.dst)].push_back(m.srcs[0].v);
      partners[static_cast<std::size_t>(m.srcs[0].v)].push_back(m.dst);
    }
  }
  std::vector<std::size_t> order;
  for (std::size_t v = 0; v < nv; ++v) {
    if (f.vregs[v].fixed < 0 && start[v] >= 0) order.push_back(v);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (vectors_first && (f.vregs[x].width >= 2) != (f.vregs[y].width >= 2)) return f.vregs[x].width >= 2;
    return start[x] < start[y];
  });
  for (const std::size_t v : order) {
    const int w = f.vregs[v].width;
    bool placed = false;
    for (const int p : partners[v]) {
      const Location& l = a.location[static_cast<std::size_t>(p)];
      if (l.reg >= 0 && free_for(l.reg, l.lane, w, v)) {
        take(v, l.reg, l.lane);
        placed = true;
        break;
      }
    }
    for (int reg = 0; reg < registers && !placed; ++reg) {
      if (w >= 2) {
        const std::array<std::uint8_t, 4> lanes{0, 1, 2, 3};
        if (free_for(reg, lanes, w, v)) {
          take(v, reg, lanes);
          placed = true;
        }
        continue;
      }
      for (int lane = 3; lane >= 0 && !placed; --lane) {
        const std::array<std::uint8_t, 4> lanes{static_cast<std::uint8_t>(lane), 0, 0, 0};
        if (free_for(reg, lanes, 1, v)) {
          take(v, reg, lanes);
          placed = true;
        }
      }
    }
    if (!placed) return static_cast<int>(v);
  }
  return -1;
}

// Spans [first, last] of the code that control enters only by falling into `first` and
// leaves only by falling out of `last`, so that a push before the span and a pop after it
// pair up on every path: the memory stack is last in, first out. Spans of earlier spills
// nest in them or lie outside them.
class Spans {
 public:
  explicit Spans(const MFunction& f)
      : f_(f), target_(cfg_of(f).target), partner_(f.code.size(), 0), branches_to_(f.code.size()) {
    std::vector<std::size_t> open;
    for (std::size_t i = 0; i < f.code.size(); ++i) {
      const MInst& m = f.code[i];
      if (target_[i] != Cfg::kNone) branches_to_[target_[i]].push_back(i);
      if (m.kind == Kind::kSpill) open.push_back(i);
      if (m.kind == Kind::kReload) {
        partner_[i] = open.back();
        partner_[open.back()] = i;
        open.pop_back();
      }
    }
  }

  // The smallest span holding instructions [a, b], if there is one.
  std::optional<std::pair<std::size_t, std::size_t>> close(std::size_t a, std::size_t b) const {
    const auto reach = [&](std::size_t k, bool& changed) {
      if (k < a) a = k, changed = true;
      if (k > b) b = k, changed = true;
    };
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t k = a; k <= b; ++k) {
        const MInst& m = f_.code[k];
        switch (m.kind) {
          case Kind::kRet:
          case Kind::kHalt:
          case Kind::kTrap:
          case Kind::kEntry: return std::nullopt;
          case Kind::kBranch:
          case Kind::kCondBranch: reach(target_[k], changed); break;
          case Kind::kLabel:
            for (const std::size_t s : branches_to_[k]) reach(s, changed);
            break;
          case Kind::kSpill:
          case Kind::kReload: reach(partner_[k], changed); break;
          default: break;
        }
      }
    }
    if (a == 0 || !falls_through(f_.code[a - 1]) || !falls_through(f_.code[b])) return std::nullopt;
    return std::make_pair(a, b);
  }

 private:
  const MFunction& f_;
  std::vector<std::size_t> target_;                   // Cfg::target
  std::vector<std::size_t> partner_;                  // kSpill <-> kReload
  std::vector<std::vector<std::size_t>> branches_to_;  // per label: the branches to it
};

// Gives each web of `u` (its definitions joined by the uses they reach together) a vreg of
// its own, so that the value a spill pops can live in another register than the one it
// was pushed from.
void split_webs(MFunction& f, int u) {
  const std::size_t n = f.code.size();
  const std::vector<std::vector<std::size_t>> preds = cfg_of(f).preds;
  std::vector<int> uses, defs;
  const auto reads = [&](std::size_t i) {
    uses_of(f.code[i], f, uses);
    return std::find(uses.begin(), uses.end(), u) != uses.end();
  };
  const auto writes = [&](std::size_t i) {
    defs_of(f.code[i], defs);
    return std::find(defs.begin(), defs.end(), u) != defs.end();
  };
  // Reaching definitions of u, forwards to a fixed point: the sets are small.
  std::vector<std::vector<std::size_t>> in(n), out(n);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<std::size_t> r;
      for (const std::size_t p : preds[i]) r.insert(r.end(), out[p].begin(), out[p].end());
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      std::vector<std::size_t> o = writes(i) ? std::vector<std::size_t>{i} : r;
      if (r != in[i] || o != out[i]) {
        changed = true;
        in[i] = std::move(r);
        out[i] = std::move(o);
      }
    }
  }
  // Union the definitions that reach one use, and a partial write with the definitions
  // it keeps the other lanes of.
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!reads(i)) continue;
    for (const std::size_t d : in[i]) parent[find(d)] = find(in[i].front());
    const MInst& m = f.code[i];
    if (m.dst == u && partial(m, f) && !m.fresh && !in[i].empty()) parent[find(i)] = find(in[i].front());
  }
  // The web of the first definition keeps u; the others get new vregs.
  std::unordered_map<std::size_t, int> web_vreg;
  for (std::size_t i = 0; i < n; ++i) {
    if (!writes(i)) continue;
    const std::size_t root = find(i);
    if (web_vreg.count(root)) continue;
    if (web_vreg.empty()) {
      web_vreg[root] = u;
    } else {
      web_vreg[root] = static_cast<int>(f.vregs.size());
      f.vregs.push_back(f.vregs[static_cast<std::size_t>(u)]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    MInst& m = f.code[i];
    if (reads(i) && !in[i].empty()) {
      const int w = web_vreg.at(find(in[i].front()));
      for (Src& s : m.srcs) {
        if (s.v == u) s.v = w;
      }
      for (int& x : m.uses) {
        if (x == u) x = w;
      }
    }
    if (writes(i)) {
      const int w = web_vreg.at(find(i));
      if (m.dst == u) m.dst = w;
      for (int& x : m.defs) {
        if (x == u) x = w;
      }
    }
  }
}

// Per vreg, the instructions that read or write it, in order.
class References {
 public:
  References(const MFunction& f, const Liveness& l) : refs_(f.vregs.size()) {
    for (std::size_t i = 0; i < f.code.size(); ++i) {
      for (int u : l.uses[i]) refs_[static_cast<std::size_t>(u)].push_back(i);
      for (int d : l.defs[i]) refs_[static_cast<std::size_t>(d)].push_back(i);
    }
  }
  bool touch(int u, std::pair<std::size_t, std::size_t> span) const {
    const auto& r = refs_[static_cast<std::size_t>(u)];
    const auto it = std::lower_bound(r.begin(), r.end(), span.first);
    return it != r.end() && *it <= span.second;
  }
  // The first instruction after i that touches u, or `none`.
  std::size_t next_after(int u, std::size_t i, std::size_t none) const {
    const auto& r = refs_[static_cast<std::size_t>(u)];
    const auto it = std::upper_bound(r.begin(), r.end(), i);
    return it == r.end() ? none : *it;
  }

 private:
  std::vector<std::vector<std::size_t>> refs_;
};

// A span that holds instruction i and reaches as far as it can towards the next
// instruction to touch u without holding it: all the way if it can, else grown from i one
// instruction at a time (a bounded number of steps).
std::optional<std::pair<std::size_t, std::size_t>> span_to_next_use(const MFunction& f, const Spans& spans,
                                                                    const References& refs, int u, std::size_t i) {
  const std::size_t next = refs.next_after(u, i, f.code.size());
  if (next > i + 1) {
    if (const auto whole = spans.close(i, next - 1); whole && !refs.touch(u, *whole)) return whole;
  }
  auto span = spans.close(i, i);
  if (!span || refs.touch(u, *span)) return std::nullopt;
  for (std::size_t steps = 0; span->second + 1 < next && steps < kMaxGrowth; ++steps) {
    const auto wider = spans.close(span->first, span->second + 1);
    if (!wider || refs.touch(u, *wider)) break;
    span = wider;
  }
  return span;
}

// Pushes u before the span and pops it after.
void insert_spill(MFunction& f, int u, std::pair<std::size_t, std::size_t> span) {
  MInst reload;
  reload.kind = Kind::kReload;
  reload.dst = u;
  reload.where = f.code[span.second].where;
  MInst spill;
  spill.kind = Kind::kSpill;
  spill.srcs = {Src{.v = u, .n = f.vregs[static_cast<std::size_t>(u)].width}};
  spill.where = f.code[span.first].where;
  f.code.insert(f.code.begin() + static_cast<std::ptrdiff_t>(span.second + 1), std::move(reload));
  f.code.insert(f.code.begin() + static_cast<std::ptrdiff_t>(span.first), std::move(spill));
  if (f.vregs[static_cast<std::size_t>(u)].fixed < 0) split_webs(f, u);
}

// Where the code is read from top to bottom, values wanted more than `registers`
// registers at once (a register per vector, 4 lanes per register): the value needed
// again last is pushed there and popped just before it is (Belady's choice; the spans of
// later spills start later, so they nest in the earlier ones or follow them). Returns
// the spills made.
int relieve_pressure(MFunction& f, int registers, int budget) {
  int spills = 0;
  for (std::size_t from = 0; spills < budget;) {
    const Liveness l = liveness(f);
    const References refs(f, l);
    const Spans spans(f);
    bool spilled = false;
    for (std::size_t i = from; i < f.code.size() && !spilled; ++i) {
      for (const int point : {static_cast<int>(2 * i), static_cast<int>(2 * i + 1)}) {
        const Bits live = live_at(l, point);
        int vectors = 0, lanes = 0;
        live.for_each([&](int x) {
          const int w = f.vregs[static_cast<std::size_t>(x)].width;
          vectors += w >= 2;
          lanes += w;
        });
        if (std::max(vectors, (lanes + 3) / 4) <= registers) continue;
        // (next touched, a vector, vreg), the value needed again last first
        std::vector<std::tuple<std::size_t, bool, int>> candidates;
        live.for_each([&](int u) {
          if (refs.touch(u, {i, i})) return;
          candidates.emplace_back(refs.next_after(u, i, f.code.size()), f.vregs[static_cast<std::size_t>(u)].width >= 2,
                                  u);
        });
        std::sort(candidates.rbegin(), candidates.rend());
        if (candidates.size() > kMaxTries) candidates.resize(kMaxTries);
        for (const auto& [next, vector, u] : candidates) {
          if (const auto span = span_to_next_use(f, spans, refs, u, i)) {
            insert_spill(f, u, *span);
            from = span->first;
            spilled = true;
            break;
          }
        }
        if (spilled) break;
      }
      if (!spilled) from = i + 1;
    }
    if (!spilled) break;
    ++spills;
  }
  return spills;
}

// Makes room where `v` did not fit: at the point of its span where no register has room
// for it (or, if each point has some but no one register has room for all of it, at the
// point where the most lanes are live; failing that, the next), the value untouched
// furthest on from there is pushed and popped before it is touched again. False if no
// value can be.
bool spill_for(MFunction& f, const Liveness& l, const std::vector<std::vector<std::pair<int, int>>>& segments,
               const LaneBusy& lane_busy, int v) {
  const int need = f.vregs[static_cast<std::size_t>(v)].width;
  const auto room_at = [&](int p) {
    for (std::size_t reg = 0; reg < lane_busy.size() / 4; ++reg) {
      int free = 0;
      for (std::size_t lane = 0; lane < 4; ++lane) free += !overlaps(lane_busy[reg * 4 + lane], p, p);
      if (need == 1 ? free > 0 : free == 4) return true;
    }
    return false;
  };
  // The points of v's span, the most pressing first: (no room, live lanes, point).
  std::vector<std::tuple<bool, int, int>> points;
  for (const auto& [s, e] : segments[static_cast<std::size_t>(v)]) {
    for (int p = s; p <= e; ++p) {
      // a spill's own push or pop is no place for another: a span holding it holds its pair
      const Kind kind = f.code[static_cast<std::size_t>(p / 2)].kind;
      if (kind == Kind::kSpill || kind == Kind::kReload) continue;
      int lanes = 0;
      live_at(l, p).for_each([&](int x) { lanes += f.vregs[static_cast<std::size_t>(x)].width; });
      points.emplace_back(!room_at(p), lanes, -p);
    }
  }
  std::sort(points.rbegin(), points.rend());
  if (points.size() > kMaxTries) points.resize(kMaxTries);
  const References refs(f, l);
  const Spans spans(f);
  int best = -1;
  std::pair<std::size_t, std::size_t> best_span;
  std::pair<bool, std::size_t> best_score{false, 0};
  for (std::size_t k = 0; k < points.size() && best < 0; ++k) {
    const int peak = -std::get<2>(points[k]);
    const auto at = static_cast<std::size_t>(peak / 2);
    live_at(l, peak).for_each([&](int u) {
      const auto span = span_to_next_use(f, spans, refs, u, at);
      if (!span) return;
      const std::pair<bool, std::size_t> score{f.vregs[static_cast<std::size_t>(u)].width >= need, span->second};
      if (best < 0 || score > best_score) best = u, best_span = *span, best_score = score;
    });
  }
  if (best < 0) return false;
  insert_spill(f, best, best_span);
  return true;
}

// The spills' pushes and pops pair up on every path: the depth of the stack they make is
// the same on every edge into an instruction and 0 where the function leaves.
void check_spills(const MFunction& f) {
  const std::size_t n = f.code.size();
  const Cfg cfg = cfg_of(f);
  std::vector<int> depth(n, -1);
  std::vector<std::size_t> work{0};
  depth[0] = 0;
  const auto reach = [&](std::size_t to, int d, std::size_t from) {
    if (depth[to] == -1) {
      depth[to] = d;
      work.push_back(to);
    } else if (depth[to] != d) {
      throw Error(fmt::format("{}: internal error: spills unbalanced at instruction {} (from {}: {} and {})", f.name,
                              to, from, depth[to], d));
    }
  };
  while (!work.empty()) {
    const std::size_t i = work.back();
    work.pop_back();
    const MInst& m = f.code[i];
    const int d = depth[i] + (m.kind == Kind::kSpill) - (m.kind == Kind::kReload);
    if (d < 0 || ((m.kind == Kind::kRet || m.kind == Kind::kHalt) && d != 0)) {
      throw Error(fmt::format("{}: internal error: spills unbalanced at instruction {}", f.name, i));
    }
    for (const std::size_t s : cfg.succ[i]) reach(s, d, i);
  }
}

}  // namespace

Allocation allocate(MFunction& f, int registers) {
  Allocation a;
  Liveness l;
  LaneBusy lane_busy;
  for (int spills = relieve_pressure(f, registers, kMaxSpills);; ++spills) {
    l = liveness(f);
    const auto segments = segments_of(f, l);
    int v = place(f, segments, registers, false, a, lane_busy);
    if (v >= 0 && place(f, segments, registers, true, a, lane_busy) < 0) v = -1;
    if (v < 0) break;
    if (spills < kMaxSpills && spill_for(f, l, segments, lane_busy, v)) continue;
    // Name the source line where the value that did not fit is made.
    const auto at = static_cast<std::size_t>(segments[static_cast<std::size_t>(v)].front().first / 2);
    SourceLocation where;
    for (std::size_t k = at + 1; k-- > 0;) {
      if (f.code[k].where.line > 0) {
        where = f.code[k].where;
        break;
      }
    }
    int live = 0;
    l.live_out[at].for_each([&](int x) { live += f.vregs[static_cast<std::size_t>(x)].width; });
    throw Error(fmt::format("{}:{}: error: the shader needs more than {} registers here ({} lanes live, {} values "
                            "spilled); simplify the code or compile for more registers (--registers)",
                            where.file.empty() ? f.name : where.file, where.line, registers, live, spills));
  }
  check_spills(f);
  // What each call must keep: the values live across it; and the stack bytes in use at
  // once (spills, and the saves at a call inside them).
  a.saves.assign(f.code.size(), {});
  int depth = 0;
  for (std::size_t i = 0; i < f.code.size(); ++i) {
    if (f.code[i].kind == Kind::kSpill) a.max_save_bytes = std::max(a.max_save_bytes, 16 * ++depth);
    if (f.code[i].kind == Kind::kReload) --depth;
    if (f.code[i].kind != Kind::kCall) continue;
    Bits across = l.live_out[i];
    for (int d : l.defs[i]) across.reset(d);
    std::map<int, std::uint8_t> regs;
    across.for_each([&](int v) {
      const Location& loc = a.location[static_cast<std::size_t>(v)];
      for (int j = 0; j < f.vregs[static_cast<std::size_t>(v)].width; ++j) {
        regs[loc.reg] |= static_cast<std::uint8_t>(1u << loc.lane[static_cast<std::size_t>(j)]);
      }
    });
    for (const auto& [reg, lanes] : regs) a.saves[i].push_back({reg, lanes});
    a.max_save_bytes = std::max(a.max_save_bytes, 16 * (depth + static_cast<int>(regs.size())));
  }
  return a;
}

Allocation pinned(const MFunction& f) {
  Allocation a;
  for (const VReg& r : f.vregs) {
    Location l{r.fixed, {0, 1, 2, 3}};
    if (r.width == 1) l.lane[0] = static_cast<std::uint8_t>(r.fixed_lane);
    a.location.push_back(l);
    a.registers_used = std::max(a.registers_used, r.fixed + 1);
  }
  a.saves.assign(f.code.size(), {});
  return a;
}

}  // namespace rpu::cc
