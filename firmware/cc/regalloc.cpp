#include "cc/regalloc.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu::cc {

namespace {

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

}  // namespace

Allocation allocate(const MFunction& f, int registers) {
  const std::size_t n = f.code.size(), nv = f.vregs.size();
  std::unordered_map<std::string, std::size_t> labels;
  for (std::size_t i = 0; i < n; ++i) {
    if (f.code[i].kind == Kind::kLabel) labels[f.code[i].target] = i;
  }
  std::vector<std::vector<std::size_t>> succ(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MInst& m = f.code[i];
    const auto target = [&] {
      const auto it = labels.find(m.target);
      if (it == labels.end()) throw Error(fmt::format("{}: internal error: no label {}", f.name, m.target));
      return it->second;
    };
    switch (m.kind) {
      case Kind::kRet:
      case Kind::kHalt: break;
      case Kind::kBranch: succ[i].push_back(target()); break;
      case Kind::kCondBranch:
        succ[i].push_back(target());
        if (i + 1 < n) succ[i].push_back(i + 1);
        break;
      default:
        if (i + 1 < n) succ[i].push_back(i + 1);
    }
  }
  // Liveness to a fixed point, backwards.
  std::vector<Bits> live_in(n, Bits(nv)), live_out(n, Bits(nv));
  std::vector<std::vector<int>> uses(n), defs(n);
  for (std::size_t i = 0; i < n; ++i) {
    uses_of(f.code[i], f, uses[i]);
    defs_of(f.code[i], defs[i]);
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = n; k-- > 0;) {
      Bits out(nv);
      for (std::size_t s : succ[k]) out.merge(live_in[s]);
      Bits in = out;
      for (int d : defs[k]) in.reset(d);
      for (int u : uses[k]) in.set(u);
      if (!(in == live_in[k]) || !(out == live_out[k])) {
        changed = true;
        live_in[k] = std::move(in);
        live_out[k] = std::move(out);
      }
    }
  }
  // Live segments over points: 2i = instruction i reads, 2i + 1 = it writes. Two vregs
  // may share a lane when no point has both live (a def always takes its write point).
  std::vector<std::vector<std::pair<int, int>>> segments(nv);
  const auto touch = [&](int v, int point) {
    auto& segs = segments[static_cast<std::size_t>(v)];
    if (!segs.empty() && segs.back().second >= point - 1) {
      segs.back().second = std::max(segs.back().second, point);
    } else {
      segs.push_back({point, point});
    }
  };
  for (std::size_t i = 0; i < n; ++i) {
    const int p = static_cast<int>(2 * i);
    live_in[i].for_each([&](int v) { touch(v, p); });
    Bits written = live_out[i];
    for (int d : defs[i]) written.set(d);
    written.for_each([&](int v) { touch(v, p + 1); });
  }
  std::vector<int> start(nv, -1);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!segments[v].empty()) start[v] = segments[v].front().first;
  }

  Allocation a;
  a.location.assign(nv, {});
  a.saves.assign(n, {});
  // Per lane, the points taken: a sorted map from segment start to end.
  std::vector<std::map<int, int>> lane_busy(static_cast<std::size_t>(registers) * 4);
  const auto overlaps = [](const std::map<int, int>& busy, int s, int e) {
    auto it = busy.upper_bound(e);  // the first segment starting after e
    if (it == busy.begin()) return false;
    --it;                           // the last segment starting at or before e
    return it->second >= s;
  };
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
    if (m.kind == Kind::kOp && m.mn == "mov" && m.dst >= 0 && m.srcs.size() == 1 && !m.srcs[0].neg &&
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
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return start[x] < start[y]; });
  for (const std::size_t v : order) {
    const int w = f.vregs[v].width;
    bool coalesced = false;
    for (const int p : partners[v]) {
      const Location& l = a.location[static_cast<std::size_t>(p)];
      if (l.reg >= 0 && free_for(l.reg, l.lane, w, v)) {
        take(v, l.reg, l.lane);
        coalesced = true;
        break;
      }
    }
    if (coalesced) continue;
    bool placed = false;
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
    if (!placed) {
      // Name the source line where the value that did not fit is made.
      const std::size_t at = static_cast<std::size_t>(start[v] / 2);
      SourceLocation where;
      for (std::size_t k = at + 1; k-- > 0;) {
        if (f.code[k].where.line > 0) {
          where = f.code[k].where;
          break;
        }
      }
      int live = 0;
      live_out[at].for_each([&](int x) { live += f.vregs[static_cast<std::size_t>(x)].width; });
      throw Error(fmt::format("{}:{}: error: the shader needs more than {} registers here ({} lanes live); simplify "
                              "the code or compile for more registers (--registers)",
                              where.file.empty() ? f.name : where.file, where.line, registers, live));
    }
  }
  // What each call must keep: the values live across it.
  for (std::size_t i = 0; i < n; ++i) {
    if (f.code[i].kind != Kind::kCall) continue;
    Bits across = live_out[i];
    for (int d : defs[i]) across.reset(d);
    std::map<int, std::uint8_t> regs;
    across.for_each([&](int v) {
      const Location& l = a.location[static_cast<std::size_t>(v)];
      for (int j = 0; j < f.vregs[static_cast<std::size_t>(v)].width; ++j) {
        regs[l.reg] |= static_cast<std::uint8_t>(1u << l.lane[static_cast<std::size_t>(j)]);
      }
    });
    for (const auto& [reg, lanes] : regs) a.saves[i].push_back({reg, lanes});
    a.max_save_bytes = std::max(a.max_save_bytes, 16 * static_cast<int>(regs.size()));
  }
  return a;
}

}  // namespace rpu::cc
