// The memory system's co-simulation (docs/memory-system.md): a Verilated
// rpu_mem_cosim_top (a node, a triangle and a data cache of a named configuration, or
// the corner cases, each behind a cache arbiter of cache ports and a traversal unit's
// in-order port, on one memory port through the memory arbiter) driven by random reads
// and writes of a few conflicting lines, every valid and ready stalled at random. The
// memory port is served by the cycle model's DRAM (cycle::Dram) over a C++ memory.
//
// Checked: every read returns the words of the latest write the cache took before it
// (a reference memory updated in the order the cache ports took the requests); tags
// pair up at every port, in-order answers come in order, nothing is answered twice or
// unasked, a hit never answers earlier than its hit latency; at the end nothing is
// left over, every cache is idle, its counters add up (hits + merged + misses =
// accesses = the reads it took, misses = its line reads, writes = its writes at the
// memory port for a write-through cache; for a write-back one, write_backs = its line
// writes and the rest of its writes at most its writes taken) and the memory holds
// every write. A write-back cache is flushed twice: halfway through its requests
// (flush_i held until it has no dirty line and is idle, the requests waiting
// meanwhile) and once every request to it is sent (some reads still in flight), so it
// writes its dirty lines, beside its last fills, before it is idle. --serial sends one request at a time
// and holds each read's hit or miss to an LRU reference of the tag array, and each
// hit's latency to the cache's hit latency exactly.
//
//   mem_cosim --model tiny --cache all --requests 20000 [--serial] [--coverage]
//             [--seed N] [--stall P] [--trace waves.fst] [--write-vectors FILE]
#include <bit>
#include <chrono>
#include <cstdio>
#include <deque>
#include <optional>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "common/output_file.hpp"
#include "cosim_core.hpp"
#include "harness_outputs.hpp"
#include "mem_agents.hpp"
#include "mem_shape.hpp"
#include "model.hpp"

namespace {

using namespace rpu;
using namespace rpu::sim;

// What the cache arbiter leaves of a cache's tag to each of its ports.
constexpr std::uint32_t kOwnTagBits =
    streams::kCacheTagBits - static_cast<std::uint32_t>(std::bit_width(kRawPorts + kInOrderPorts - 1));
constexpr std::uint32_t kPieceWords = streams::kMemLineBytes / 4;

struct Options {
  std::string model = "tiny";
  std::string cache = "all";
  std::uint64_t requests = 20000;  // per cache with traffic
  bool serial = false;
  bool coverage = false;
  double writes = 0.3;
  double stall = 0.1;
  std::uint64_t seed = 1;
  std::string trace, vectors;
};

using MemModel = Model<harness::Mem>;
using MemRecorder = RecordingModel<harness::Mem>;

// A cache port's requester: random reads and writes, each tag in flight at most once.
struct RawPort {
  std::size_t cache = 0, index = 0;
  std::vector<std::uint32_t> free_tags;
  std::optional<streams::CacheReq> presented;
  std::uint64_t since = 0;  // the cycle it was first presented
  PendingByTag<ExpectedRead> reads{"cache_req read", "cache_rsp", static_cast<int>(streams::kCacheTagBits)};
};

// A traversal unit's port: reads, answered in order.
struct InOrderPort {
  std::size_t cache = 0, index = 0;
  std::optional<streams::MemReq> presented;
  std::deque<ExpectedRead> reads;
};

struct CacheRun {
  streams::CacheGeometry geometry;
  bool active = false;
  std::optional<AddressPicker> picker;
  std::uint64_t budget = 0;  // requests still to send
  // Write-back: a flush halfway through its requests (held until no line is dirty and
  // the cache is idle), then one after the last; the flushes that began with a dirty
  // line, and the whole lines written to memory while flush_i was high.
  bool flushed_halfway = false, flushing_halfway = false;
  std::uint64_t flushes_of_dirty_lines = 0, line_writes_flushing = 0;
  std::uint64_t reads = 0, writes = 0;
  std::uint64_t writes_on_fill = 0;  // writes presented while their line was being read
  std::optional<LruReference> lru;
};

// A read for a failure's message (`kind` "cache" or "in-order" port; the tag if known).
std::string describe(const char* kind, std::size_t cache, std::size_t port, std::optional<std::uint32_t> tag,
                     const ExpectedRead& e) {
  return fmt::format("{} cache, {} port {}{}: read of {:#010x} taken at cycle {}", kCacheNames[cache], kind, port,
                     tag ? fmt::format(", tag {:#x}", *tag) : "", e.addr, e.taken);
}

std::string words(const std::array<std::uint32_t, kPieceWords>& w) {
  return fmt::format("{:08x} {:08x} {:08x} {:08x}", w[3], w[2], w[1], w[0]);
}

struct MissTiming {
  std::uint64_t misses = 0, total = 0, before = 0, dram = 0, after = 0;
};

class Harness {
 public:
  Harness(const Options& o, MemModel& model, const spec::DramConfig& dram)
      : o_(o), model_(model), clock_(model), stalls_(o.seed, o.stall), dram_(dram) {
    harness::Mem::Outputs geometry;
    model.read_on_demand(geometry);
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      CacheRun& cr = caches_[c];
      cr.geometry = geometry.geometry[c];
      cr.active = o.cache == "all" || o.cache == kCacheNames[c];
      cr.picker.emplace(c, cr.geometry, stalls_.rng());
      cr.budget = cr.active ? o.requests : 0;
      if (o.serial) cr.lru.emplace(cr.geometry);
    }
    for (std::size_t p = 0; p < kRaw; ++p) {
      raw_[p].cache = p / kRawPorts;
      raw_[p].index = p % kRawPorts;
      for (std::uint32_t t = 0; t < (1u << kOwnTagBits); ++t) raw_[p].free_tags.push_back(t);
    }
    for (std::size_t p = 0; p < kInOrder; ++p) {
      inorder_[p].cache = p / kInOrderPorts;
      inorder_[p].index = p % kInOrderPorts;
    }
  }

  void run(MemRecorder* recorder);
  void report(double seconds) const;

 private:
  void present_raw(RawPort& port, bool idle);
  void present_inorder(InOrderPort& port);
  void take_raw(RawPort& port, std::uint64_t now);
  void answer_raw(RawPort& port, const streams::CacheRsp& rsp, std::uint64_t now);
  void check_serial_answer(std::size_t cache, const ExpectedRead& e, std::uint64_t now, const char* where);
  void finish();
  bool traffic_left() const;
  bool requests_left(std::size_t cache) const;
  bool may_start(std::size_t cache) const { return caches_[cache].budget > 0; }

  const Options& o_;
  MemModel& model_;
  Clock<MemModel> clock_;
  Stalls stalls_;
  DramServer dram_;
  WordMemory reference_;
  std::array<CacheRun, kMemCaches> caches_;
  std::array<RawPort, kRaw> raw_;
  std::array<InOrderPort, kInOrder> inorder_;
  harness::Mem::Inputs in_;
  harness::Mem::Outputs out_;
  // --serial: the counters when the outstanding read was taken, and its miss timing.
  streams::CacheCounters serial_before_;
  std::uint64_t dram_taken_ = 0, dram_answered_ = 0;
  MissTiming miss_timing_;
  bool took_ = false;  // a request was taken in the last cycle
};

void Harness::present_raw(RawPort& port, bool idle) {
  CacheRun& cr = caches_[port.cache];
  if (port.presented || !may_start(port.cache)) return;
  if (o_.serial) {
    // One request at a time, on the first port: the last one answered and drained.
    if (port.index != 0 || !port.reads.empty() || !idle) return;
  } else if (stalls_()) {
    return;
  }
  const bool write = std::bernoulli_distribution(o_.writes)(stalls_.rng()) || port.free_tags.empty();
  streams::CacheReq req;
  req.addr = cr.picker->pick(stalls_.rng());
  req.write = write;
  if (write) {
    req.wmask = std::uniform_int_distribution<std::uint32_t>(1, (1u << kPieceWords) - 1)(stalls_.rng());
    for (std::uint32_t& w : req.data) w = static_cast<std::uint32_t>(stalls_.rng()());
    const std::uint32_t line = req.addr & ~(streams::kDramLineBytes - 1);
    if (dram_.reading(line)) ++cr.writes_on_fill;
  } else {
    const auto pick = std::uniform_int_distribution<std::size_t>(0, port.free_tags.size() - 1)(stalls_.rng());
    req.tag = port.free_tags[pick];
    port.free_tags.erase(port.free_tags.begin() + static_cast<std::ptrdiff_t>(pick));
  }
  port.presented = req;
  port.since = clock_.cycle();
  --cr.budget;
}

void Harness::present_inorder(InOrderPort& port) {
  if (port.presented || !may_start(port.cache) || o_.serial || stalls_()) return;
  streams::MemReq req;
  req.addr = caches_[port.cache].picker->pick(stalls_.rng());
  req.tag = std::uniform_int_distribution<std::uint32_t>(0, (1u << streams::kCacheTagBits) - 1)(stalls_.rng());
  port.presented = req;
  --caches_[port.cache].budget;
}

void Harness::take_raw(RawPort& port, std::uint64_t now) {
  CacheRun& cr = caches_[port.cache];
  const streams::CacheReq& req = *port.presented;
  if (req.write) {
    for (std::uint32_t k = 0; k < kPieceWords; ++k) {
      if (req.wmask >> k & 1) reference_.store(req.addr + 4 * k, req.data[k]);
    }
    ++cr.writes;
  } else {
    ExpectedRead e;
    e.addr = req.addr;
    e.taken = now;
    for (std::uint32_t k = 0; k < kPieceWords; ++k) e.data[k] = reference_.load(req.addr + 4 * k);
    if (cr.lru) {
      e.hit = cr.lru->read(req.addr / streams::kDramLineBytes);
      serial_before_ = out_.counters[port.cache];
    }
    port.reads.add(req.tag, e);
    ++cr.reads;
  }
  port.presented.reset();
}

void Harness::check_serial_answer(std::size_t cache, const ExpectedRead& e, std::uint64_t now, const char* where) {
  const CacheRun& cr = caches_[cache];
  const streams::CacheCounters& c = out_.counters[cache];
  const std::uint32_t hits = c.hits - serial_before_.hits, misses = c.misses - serial_before_.misses,
                      merged = c.merged - serial_before_.merged;
  const bool rtl_hit = hits == 1 && misses == 0 && merged == 0;
  const bool rtl_miss = hits == 0 && misses == 1 && merged == 0;
  if ((e.hit && !rtl_hit) || (!e.hit && !rtl_miss)) {
    throw CosimFailure(fmt::format("{}: the LRU reference says {} (line {:#x}, set {}), the cache counted {} hit(s), "
                                   "{} miss(es), {} merged",
                                   where, e.hit ? "hit" : "miss", e.addr / streams::kDramLineBytes,
                                   e.addr / streams::kDramLineBytes % cache_sets(cr.geometry), hits, misses, merged));
  }
  const std::uint64_t latency = now - e.taken;
  if (e.hit && latency != cr.geometry.hit_latency) {
    throw CosimFailure(fmt::format("{}: a hit answered after {} cycles; the cache's hit latency is {}", where, latency,
                                   cr.geometry.hit_latency));
  }
  if (!e.hit) {
    ++miss_timing_.misses;
    miss_timing_.total += latency;
    miss_timing_.before += dram_taken_ - e.taken;
    miss_timing_.dram += dram_answered_ - dram_taken_;
    miss_timing_.after += now - dram_answered_;
  }
}

void Harness::answer_raw(RawPort& port, const streams::CacheRsp& rsp, std::uint64_t now) {
  const ExpectedRead e = port.reads.take(rsp.tag);
  const std::string where = describe("cache", port.cache, port.index, rsp.tag, e);
  if (rsp.data != e.data) {
    throw CosimFailure(fmt::format("{}, answered at cycle {}: data {} (word 3 first), expected {}", where, now,
                                   words(rsp.data), words(e.data)));
  }
  if (now - e.taken < caches_[port.cache].geometry.hit_latency) {
    throw CosimFailure(fmt::format("{}: answered after {} cycles, under the hit latency {}", where, now - e.taken,
                                   caches_[port.cache].geometry.hit_latency));
  }
  if (o_.serial) check_serial_answer(port.cache, e, now, where.c_str());
  port.free_tags.push_back(rsp.tag);
}

bool Harness::requests_left(std::size_t cache) const {
  if (caches_[cache].budget > 0) return true;
  for (const RawPort& p : raw_) {
    if (p.cache == cache && p.presented) return true;
  }
  for (const InOrderPort& p : inorder_) {
    if (p.cache == cache && p.presented) return true;
  }
  return false;
}

bool Harness::traffic_left() const {
  for (std::size_t c = 0; c < kMemCaches; ++c) {
    if (requests_left(c)) return true;
  }
  for (const RawPort& p : raw_) {
    if (!p.reads.empty()) return true;
  }
  for (const InOrderPort& p : inorder_) {
    if (!p.reads.empty()) return true;
  }
  // Writes are not answered: the caches' idle_o says when they have left (and, with
  // write-back, their dirty lines), from the cycle after they were taken.
  if (took_) return true;
  for (std::size_t c = 0; c < kMemCaches; ++c) {
    if (!out_.idle[c] || out_.dirty[c]) return true;
  }
  return !dram_.idle();
}

void Harness::run(MemRecorder* recorder) {
  clock_.reset(in_);
  out_ = clock_.settle(in_);  // the idle outputs before the first cycle
  // From here every settle is a cycle the netlist testbench replays (one clock each).
  if (recorder) recorder->start();
  Watchdog watchdog(100'000);
  while (traffic_left()) {
    const std::uint64_t now = clock_.cycle();
    // Inputs: what each agent presents this cycle, from the last cycle's outputs.
    for (RawPort& p : raw_) {
      bool idle = true;
      for (const bool i : out_.idle) idle = idle && i;
      present_raw(p, idle);
      const std::size_t k = p.cache * kRawPorts + p.index;
      in_.req_valid[k] = p.presented.has_value();
      if (p.presented) in_.req[k] = *p.presented;
      in_.rsp_ready[k] = o_.serial || !stalls_();
    }
    for (InOrderPort& p : inorder_) {
      present_inorder(p);
      const std::size_t k = p.cache * kInOrderPorts + p.index;
      in_.mem_req_valid[k] = p.presented.has_value();
      if (p.presented) in_.mem_req[k] = *p.presented;
      in_.mem_rsp_ready[k] = !stalls_();
    }
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      CacheRun& cr = caches_[c];
      if (cr.geometry.write_back && !cr.flushed_halfway && cr.budget <= o_.requests / 2) {
        cr.flushed_halfway = cr.flushing_halfway = true;
      }
      if (cr.flushing_halfway && in_.flush[c] && !out_.dirty[c] && out_.idle[c]) cr.flushing_halfway = false;
      const bool flush = cr.flushing_halfway || !requests_left(c);
      if (flush && !in_.flush[c] && out_.dirty[c]) ++cr.flushes_of_dirty_lines;
      in_.flush[c] = flush;
    }
    in_.dram_req_ready = !stalls_();
    const streams::DramRsp* dram_rsp = dram_.offer(now, !stalls_());
    in_.dram_rsp_valid = dram_rsp != nullptr;
    if (dram_rsp) in_.dram_rsp = *dram_rsp;

    out_ = clock_.settle(in_);

    // Transfers. At most one request a cycle enters each cache (its arbiter's port).
    std::array<int, kMemCaches> taken{};
    took_ = false;
    bool progress = false;
    for (RawPort& p : raw_) {
      const std::size_t k = p.cache * kRawPorts + p.index;
      if (out_.rsp_valid[k] && in_.rsp_ready[k]) {
        answer_raw(p, out_.rsp[k], now);
        progress = true;
      }
      if (in_.req_valid[k] && out_.req_ready[k]) {
        take_raw(p, now);
        ++taken[p.cache];
        progress = true;
      }
    }
    for (InOrderPort& p : inorder_) {
      const std::size_t k = p.cache * kInOrderPorts + p.index;
      if (out_.mem_rsp_valid[k] && in_.mem_rsp_ready[k]) {
        if (p.reads.empty()) {
          throw CosimFailure(fmt::format("{} cache, in-order port {}: an answer at cycle {} with no read in flight",
                                         kCacheNames[p.cache], p.index, now));
        }
        const ExpectedRead e = p.reads.front();
        p.reads.pop_front();
        if (out_.mem_rsp[k].data != e.data || out_.mem_rsp[k].tag != e.tag) {
          throw CosimFailure(fmt::format("{}, answered at cycle {} (in request order): tag {:x}, data {} (word 3 "
                                         "first), expected tag {:x}, data {}",
                                         describe("in-order", p.cache, p.index, std::nullopt, e), now,
                                         out_.mem_rsp[k].tag, words(out_.mem_rsp[k].data), e.tag, words(e.data)));
        }
        progress = true;
      }
      if (in_.mem_req_valid[k] && out_.mem_req_ready[k]) {
        ExpectedRead e;
        e.addr = p.presented->addr;
        e.tag = p.presented->tag;
        e.taken = now;
        for (std::uint32_t w = 0; w < kPieceWords; ++w) e.data[w] = reference_.load(e.addr + 4 * w);
        p.reads.push_back(e);
        p.presented.reset();
        ++caches_[p.cache].reads;
        ++taken[p.cache];
        progress = true;
      }
    }
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      took_ = took_ || taken[c] > 0;
      if (taken[c] > 1) {
        throw CosimFailure(fmt::format("{} requests entered the {} cache in cycle {}; its port takes one", taken[c],
                                       kCacheNames[c], now));
      }
    }
    if (out_.dram_req_valid && in_.dram_req_ready) {
      const std::size_t cache = out_.dram_req.tag >> streams::kDramMshrBits;
      if (out_.dram_req.write && cache < kMemCaches && in_.flush[cache] &&
          std::popcount(out_.dram_req.wmask) == static_cast<int>(streams::kDramLineBytes / 4)) {
        ++caches_[cache].line_writes_flushing;
      }
      dram_.take(out_.dram_req, now);
      if (!out_.dram_req.write) dram_taken_ = now;
      progress = true;
    }
    if (in_.dram_rsp_valid && out_.dram_rsp_ready) {
      dram_.taken();
      dram_answered_ = now;
      progress = true;
    }
    if (progress) watchdog.progress(now);
    watchdog.check(now, traffic_left(), [&] {
      for (const RawPort& p : raw_) {
        if (!p.reads.empty()) {
          return describe("cache", p.cache, p.index, std::nullopt, p.reads.oldest()) + " is not answered";
        }
        if (p.presented) {
          return fmt::format("{} cache, cache port {}: a request presented at cycle {} is not taken",
                             kCacheNames[p.cache], p.index, p.since);
        }
      }
      for (const InOrderPort& p : inorder_) {
        if (!p.reads.empty()) {
          return describe("in-order", p.cache, p.index, std::nullopt, p.reads.front()) + " is not answered";
        }
      }
      return std::string("a request or a line read is stuck");
    });
    clock_.tick();
  }
  finish();
}

void Harness::finish() {
  // Nothing more may come out: answers nobody asked for, memory requests.
  harness::Mem::Inputs idle = in_;
  idle.req_valid.fill(false);
  idle.mem_req_valid.fill(false);
  idle.rsp_ready.fill(true);
  idle.mem_rsp_ready.fill(true);
  idle.dram_req_ready = true;
  idle.dram_rsp_valid = false;
  expect_quiet(clock_, idle, 64, [&](const harness::Mem::Outputs& out) -> std::string {
    for (std::size_t k = 0; k < kRaw; ++k) {
      if (out.rsp_valid[k]) return fmt::format("cache_rsp on cache port {} with tag {:#x}", k, out.rsp[k].tag);
    }
    for (std::size_t k = 0; k < kInOrder; ++k) {
      if (out.mem_rsp_valid[k]) return fmt::format("mem_rsp on in-order port {}", k);
    }
    if (out.dram_req_valid) return fmt::format("dram_req at {:#010x}", out.dram_req.addr);
    out_ = out;
    return "";
  });
  for (std::size_t c = 0; c < kMemCaches; ++c) {
    const CacheRun& cr = caches_[c];
    const streams::CacheCounters& k = out_.counters[c];
    const DramServer::CacheCounts& d = dram_.counts()[c];
    const char* name = kCacheNames[c];
    if (!out_.idle[c]) throw CosimFailure(fmt::format("the {} cache is not idle after every answer", name));
    if (out_.dirty[c]) throw CosimFailure(fmt::format("the {} cache holds a dirty line after its flush", name));
    const auto check = [&](const char* what, std::uint64_t got, std::uint64_t want, const char* source) {
      if (got != want) {
        throw CosimFailure(fmt::format("{} cache: counter {} is {}, {} is {}", name, what, got, source, want));
      }
    };
    check("accesses", k.accesses, cr.reads, "the reads its ports took");
    check("hits + merged + misses", std::uint64_t{k.hits} + k.merged + k.misses, k.accesses, "accesses");
    check("misses", k.misses, d.reads, "its line reads at the memory port");
    check("writes", k.writes, cr.writes, "the writes its ports took");
    if (cr.geometry.write_back == 0) {
      check("writes", k.writes, d.writes, "its writes at the memory port");
      check("write_backs", k.write_backs, 0, "a write-through cache's");
    } else {
      check("write_backs", k.write_backs, d.line_writes, "its whole-line writes at the memory port");
      if (d.writes - d.line_writes > k.writes) {
        throw CosimFailure(fmt::format("{} cache: {} writes of pieces at the memory port, more than the {} writes it took",
                                       name, d.writes - d.line_writes, k.writes));
      }
    }
    if (o_.coverage && cr.active) {
      // The traffic must have exercised what the checks are about.
      const std::uint64_t in_flight = (kRawPorts + kInOrderPorts) << kOwnTagBits;
      const auto need = [&](const char* what, std::uint64_t n) {
        if (n == 0) throw CosimFailure(fmt::format("{} cache: the traffic made no {} (raise --requests)", name, what));
      };
      need("hit", k.hits);
      need("merged read", k.merged);
      need("miss", k.misses);
      need("eviction (a line read twice)", d.refetches);
      need("write to a line being filled", cr.writes_on_fill);
      if (cr.geometry.write_back != 0) {
        need("write kept in the cache (a write to a present line)", k.writes - (d.writes - d.line_writes));
        need("dirty line evicted by a fill (a whole line written while not flushing)",
             d.line_writes - cr.line_writes_flushing);
        need("flush that began with a dirty line", cr.flushes_of_dirty_lines);
        need("dirty line written while flushing", cr.line_writes_flushing);
      }
      // The miss registers fill when more distinct lines miss at once than there are
      // registers: reads in flight and hot lines both must outnumber them (a cold line,
      // a tenth of the reads, only rarely adds the one more).
      if (cr.geometry.mshrs < std::min(in_flight, cr.picker->hot_lines())) {
        need("wait for a miss register", k.mshr_wait);
      }
    }
  }
  // After the flush: the memory holds every word the reference does.
  for (const std::uint32_t a : reference_.written()) {
    if (dram_.memory().load(a) != reference_.load(a)) {
      throw CosimFailure(fmt::format("after the run the memory holds {:08x} at {:#010x}; the last write was {:08x}",
                                     dram_.memory().load(a), a, reference_.load(a)));
    }
  }
}

void Harness::report(double seconds) const {
  const std::uint64_t cycles = clock_.cycle();
  fmt::print("mem_cosim ok: model {}, {} cache(s), {} cycles, {:.2f} s, {:.0f} cycles/s\n", o_.model, o_.cache, cycles,
             seconds, static_cast<double>(cycles) / std::max(seconds, 1e-9));
  for (std::size_t c = 0; c < kMemCaches; ++c) {
    const CacheRun& cr = caches_[c];
    if (!cr.active) continue;
    const streams::CacheCounters& k = out_.counters[c];
    const DramServer::CacheCounts& d = dram_.counts()[c];
    fmt::print("  {} ({} B, {} ways, {} sets, hit latency {}, {} MSHRs, {}): {} reads, {} writes; accesses {}, "
               "hits {}, merged {}, misses {}, writes {}, write_backs {}, mshr_wait {}; line reads {} ({} refetched), "
               "writes {} ({} of whole lines), writes to a filling line {}\n",
               kCacheNames[c], cr.geometry.bytes, cr.geometry.ways, cache_sets(cr.geometry), cr.geometry.hit_latency,
               cr.geometry.mshrs, cr.geometry.write_back ? "write-back" : "write-through", cr.reads, cr.writes,
               k.accesses, k.hits, k.merged, k.misses, k.writes, k.write_backs, k.mshr_wait, d.reads, d.refetches,
               d.writes, d.line_writes, cr.writes_on_fill);
  }
  const cycle::DramStats& s = dram_.dram().stats();
  fmt::print("  DRAM: {} reads, {} writes, bus busy {:.1f}% of cycles\n", s.reads, s.writes,
             100.0 * static_cast<double>(s.bus_cycles) / static_cast<double>(std::max<std::uint64_t>(cycles, 1)));
  if (miss_timing_.misses) {
    const auto avg = [&](std::uint64_t x) {
      return static_cast<double>(x) / static_cast<double>(miss_timing_.misses);
    };
    fmt::print("  a miss, one request at a time: {:.1f} cycles from the take to the answer = {:.1f} to the memory "
               "port + {:.1f} in DRAM + {:.1f} from the line's arrival (install, replay, hit latency)\n",
               avg(miss_timing_.total), avg(miss_timing_.before), avg(miss_timing_.dram), avg(miss_timing_.after));
  }
}

int run(const Options& o, std::unique_ptr<MemModel>& model, std::unique_ptr<OutputFile>& vectors) {
  const ModelInfo* info = find_model<harness::Mem>({{"name", o.model}});
  if (!info) {
    throw Error(fmt::format("no memory-system model '{}' in this build (built: {})", o.model,
                            built_models<harness::Mem>()));
  }
  const std::string dram_config(info->fact("dram"));
  model = make_model<harness::Mem>(*info, o.seed, o.trace);
  if (o.serial && o.cache == "all") throw Error("--serial runs one cache: name it with --cache");
  MemRecorder* recorder = nullptr;
  if (!o.vectors.empty()) {
    if (!vectors) vectors = std::make_unique<OutputFile>(o.vectors);
    auto recording = std::make_unique<MemRecorder>(std::move(model), vectors->stream());
    recorder = recording.get();
    model = std::move(recording);
  }

  // A named configuration's model must have that configuration's caches.
  harness::Mem::Outputs geometry;
  model->read_on_demand(geometry);
  if (o.model == dram_config) {
    const spec::HardwareConfig& hc = hardware_config(o.model);
    const spec::CacheConfig* want[kMemCaches] = {&hc.node_cache, &hc.triangle_cache, &hc.data_cache};
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      const streams::CacheGeometry& g = geometry.geometry[c];
      const spec::CacheConfig& w = *want[c];
      if (g.bytes != static_cast<std::uint32_t>(w.bytes) || g.ways != static_cast<std::uint32_t>(w.ways) ||
          g.hit_latency != static_cast<std::uint32_t>(w.hit_latency) ||
          g.mshrs != static_cast<std::uint32_t>(w.mshrs) || g.write_back != static_cast<std::uint32_t>(w.write_back)) {
        throw Error(fmt::format("model '{}': its {} cache differs from spec/configs.toml's (rebuild)", o.model,
                                kCacheNames[c]));
      }
    }
  }

  Harness harness(o, *model, hardware_config(dram_config).dram);
  const auto start = std::chrono::steady_clock::now();
  harness.run(recorder);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (vectors) {
    vectors->commit();
    vectors.reset();
  }
  harness.report(seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Co-simulate the RTL memory system (caches, arbiters, in-order ports) against a data oracle and the "
               "cycle model's DRAM (docs/memory-system.md)"};
  Options o;
  app.add_option("--model", o.model, "a named configuration's memory system, or corners");
  app.add_option("--cache", o.cache, "the cache that gets traffic")
      ->check(CLI::IsMember({"node", "triangle", "data", "all"}));
  app.add_option("--requests", o.requests, "requests per cache with traffic")->check(CLI::Range(1ull, 1ull << 40));
  app.add_flag("--serial", o.serial,
               "one request at a time on one port: each read's hit or miss against an LRU reference, each hit's "
               "latency exactly the hit latency");
  app.add_flag("--coverage", o.coverage,
               "fail unless every cache with traffic saw hits, merges, misses, evictions, writes to a line being "
               "filled and (with fewer miss registers than reads in flight and hot lines) waits for a miss register");
  app.add_option("--writes", o.writes, "share of a cache port's requests that are writes")->check(CLI::Range(0.0, 1.0));
  app.add_option("--stall", o.stall, "probability that a valid or a ready stalls in a cycle")
      ->check(CLI::Range(0.0, 0.9));
  app.add_option("--seed", o.seed, "seed of the RTL's initial values, the traffic and the stalls");
  app.add_option("--trace", o.trace, "write FST waveforms here");
  app.add_option("--write-vectors", o.vectors, "write every cycle's ports here (rtl/flow.py's netlist testbench)");
  CLI11_PARSE(app, argc, argv);
  report_sigbus_as_write_failure("mem_cosim");
  std::unique_ptr<MemModel> model;
  std::unique_ptr<OutputFile> vectors;
  return run_harness("mem_cosim", o.trace, o.vectors, model, [&](std::unique_ptr<MemModel>& m) {
    try {
      return run(o, m, vectors);
    } catch (const CosimFailure& e) {
      throw CosimFailure(fmt::format("model {}, seed {}: {}", o.model, o.seed, e.what()));
    }
  });
}
