// Ray-level co-simulation of the RTL traversal unit against the golden tracer
// (rpu::functional::Tracer, SoftArith in the same format; docs/rtl.md, "Traversal
// unit"). The scene's memory image is served to the unit's memory port by a
// behavioural memory (fixed latency plus a random extra delay; responses in order to a
// walker, by tag in any order to a pipelined unit);
// without the RTL IU the harness answers the unit's IU port with the C++ intersection
// unit built from the request's fields. Camera, random, shadow (any-hit) rays and rays
// from origins exactly on the tree's split planes go through the unit's valid/ready
// ports with random stalls on every port; each response is paired with its ray by tag
// and compared bit for bit: hit, t, u, v, prim and the counters, or the stack-overflow
// fault. The first mismatch stops the run.
//
// It also measures the unit's cycles besides memory and IU waits per ray and checks
// that they are setup + inner * inner nodes + leaf * leaves + pop * pops for fixed
// constants (--timing prints them, --expect-timing compares them with the config's).
//
//   tu_cosim --scene cornell --format rpu24 --isect watertight --rays 10000 [--with-iu]
//   tu_cosim --scene cornell --format fp16 --rays 3334 --write-vectors FILE
//   tu_cosim --scene cornell --scale -60 --isect watertight --with-iu --rays 500
//
// --write-vectors needs no Verilated model: it writes the memory image, the unit's
// configuration and the rays with the Tracer's results and IU tests for the netlist
// testbench (sim/rpu_tu_netlist_tb.sv, rtl/flow.py synth --unit tu).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <ostream>
#include <map>
#include <optional>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "cosim_core.hpp"
#include "cycle/tu_pipe_timing.hpp"
#include "cycle/walker_timing.hpp"
#include "fp/format.hpp"
#include "functional/arith.hpp"
#include "functional/intersection_unit.hpp"
#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "harness_outputs.hpp"
#include "host_setup.hpp"
#include "iu_test_request.hpp"
#include "kdtree/kdtree.hpp"
#include "model.hpp"
#include "rpu/harness/tu.hpp"
#include "scene/geometry.hpp"
#include "scene/resolve.hpp"
#include "trace_fixtures.hpp"

namespace rpu::sim {
namespace {

using functional::TraceHit;
using functional::TraceMode;
using functional::TraceRay;

struct Options {
  std::string scene = "cornell";
  std::string format = "fp32";
  std::string isect = "woop";
  bool with_iu = false;
  int slots = 1;      // the model's ray slots
  bool pipe = false;  // ... sharing a node-step pipeline (rpu_tu_pipe)
  int packet = 1;     // ... each slot a packet of this many rays (rpu_tu_pipe's Packet)
  int in_flight = 1;  // rays the harness keeps in the unit at once
  int scale = 0;  // the scene times 2^scale (kd space, docs/traversal.md §1)
  int rays = 10000;  // per kind: camera, random, shadow
  int plane_rays = -1;  // from origins on split planes; -1: a tenth of rays
  std::uint64_t seed = 1;
  int mem_latency = 4, mem_jitter = 6;
  int mem_spread = 0;  // a line's extra delay by its address, up to
  int iu_latency = 6, iu_jitter = 4;
  double stall = 0.08;  // probability a port is stalled in a cycle
  bool timing = false;
  std::string expect_timing;
  std::string trace;
  std::string write_vectors;
  std::string cycle_model;        // a named configuration whose step cycles time the same rays
  double cycle_tolerance = 2.0;   // percent the model's cycles may differ from the RTL's
};

enum class Kind { kCamera, kRandom, kShadow, kPlane };
const char* kind_name(Kind k) {
  constexpr const char* names[] = {"camera", "random", "shadow", "split-plane"};
  return names[static_cast<int>(k)];
}

struct Case {
  TraceRay ray;
  Kind kind;
  TraceMode mode;
  TraceHit expect;
  bool fault = false;
  std::uint32_t pops = 0;
  functional::TraceLog log{};  // the walk, for the cycle model
};

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

std::string describe_ray(const Case& c) {
  char text[512];
  const TraceRay& r = c.ray;
  std::snprintf(text, sizeof text,
                "%s ray, %s mode: origin (%.9g, %.9g, %.9g) [%08x %08x %08x] direction (%.9g, %.9g, %.9g) "
                "[%08x %08x %08x] t_min %.9g [%08x] t_max %.9g [%08x]",
                kind_name(c.kind), c.mode == TraceMode::kAny ? "any-hit" : "closest-hit", r.origin[0], r.origin[1],
                r.origin[2], bits(r.origin[0]), bits(r.origin[1]), bits(r.origin[2]), r.direction[0], r.direction[1],
                r.direction[2], bits(r.direction[0]), bits(r.direction[1]), bits(r.direction[2]), r.t_min,
                bits(r.t_min), r.t_max, bits(r.t_max));
  return text;
}

// The ray as the unit's request: fp32 bits.
streams::TuReq request_of(const Case& c, std::uint32_t tag) {
  streams::TuReq req;
  req.tag = tag;
  for (int i = 0; i < 3; ++i) {
    req.origin[i] = bits(c.ray.origin[i]);
    req.direction[i] = bits(c.ray.direction[i]);
  }
  req.t_min = bits(c.ray.t_min);
  req.t_max = bits(c.ray.t_max);
  req.any_hit = c.mode == TraceMode::kAny;
  return req;
}

// What the unit must answer for a ray, and the bits compared (`care`): the tag and the
// fault always; without a fault hit and the counters; on a hit t, u, v and prim too.
struct Expected {
  streams::TuRsp rsp, care;
};

Expected expected_of(const Case& c, std::uint32_t tag) {
  constexpr std::uint32_t kAll = ~std::uint32_t{0};
  Expected x;
  x.rsp.tag = tag;
  x.care.tag = kAll;
  x.rsp.fault = c.fault;
  x.care.fault = kAll;
  if (c.fault) return x;
  const TraceHit& e = c.expect;
  x.rsp.hit = e.hit;
  x.rsp.nodes = e.counters.nodes;
  x.rsp.leaves = e.counters.leaves;
  x.rsp.tests = e.counters.tests;
  x.care.hit = x.care.nodes = x.care.leaves = x.care.tests = kAll;
  if (e.hit) {
    x.rsp.t = bits(e.t);
    x.rsp.u = bits(e.u);
    x.rsp.v = bits(e.v);
    x.rsp.prim = e.prim;
    x.care.t = x.care.u = x.care.v = x.care.prim = kAll;
  }
  return x;
}

// Shadow rays: from the camera rays' hit points toward the lights (a point light's
// position, an area light's centre), any-hit, stopping short of the light.
std::vector<TraceRay> shadow_rays(const Scene& scene, const std::vector<TraceRay>& camera,
                                  const functional::Tracer& tracer, int count) {
  std::vector<glm::dvec3> lights;
  for (const Light& l : scene.lights) {
    lights.push_back(l.kind == LightKind::kArea ? l.position + 0.5 * (l.edge_u + l.edge_v) : l.position);
  }
  if (lights.empty()) {
    const Bounds b = scene_bounds(scene);
    lights.push_back(b.hi + 0.25 * (b.hi - b.lo));
  }
  std::vector<TraceRay> rays;
  for (std::size_t i = 0; rays.size() < static_cast<std::size_t>(count) && i < 8 * camera.size(); ++i) {
    const TraceRay& c = camera[i % camera.size()];
    const TraceHit h = tracer.trace(c, TraceMode::kClosest);
    if (!h.hit) continue;
    // Later passes over the camera rays aim at points around the light.
    const double spread = 0.05 * static_cast<double>(i / camera.size());
    const glm::dvec3 target = lights[i % lights.size()] + spread * glm::dvec3(std::sin(i), std::cos(i), 0.5);
    TraceRay s;
    for (int k = 0; k < 3; ++k) {
      s.origin[k] = c.origin[k] + h.t * c.direction[k];
      s.direction[k] = static_cast<float>(target[k] - s.origin[k]);
    }
    s.t_min = 1e-4f;
    s.t_max = 1.0f - 1e-4f;
    rays.push_back(s);
  }
  return rays;
}

// The C++ intersection unit on the fields of the TU's request.
streams::IuRsp iu_answer(const functional::SoftArith& ar, bool watertight, const streams::IuReq& q,
                         std::mt19937_64& rng) {
  functional::RayRegisters<functional::SoftArith> ray;
  for (int i = 0; i < 3; ++i) {
    ray.origin[i] = q.origin[i];
    ray.direction[i] = q.direction[i];
  }
  ray.t_min = q.t_min;
  ray.kx = q.kx;
  ray.ky = q.ky;
  ray.kz = q.kz;
  ray.shear_x = q.shear_x;
  ray.shear_y = q.shear_y;
  functional::UnitHit<functional::SoftArith> hit;
  const bool found = watertight ? functional::intersect_watertight(ar, ray, q.record, q.t_best, hit)
                                : functional::intersect_woop(ar, ray, q.record, q.t_best, hit);
  streams::IuRsp r;
  r.tag = q.tag;
  r.hit = found;
  // A miss carries random t, u, v: the unit must ignore them.
  r.t = found ? hit.t : static_cast<std::uint32_t>(rng());
  r.u = found ? hit.u : static_cast<std::uint32_t>(rng());
  r.v = found ? hit.v : static_cast<std::uint32_t>(rng());
  return r;
}

// busy = setup + inner * inner nodes + leaf * leaves + pop * pops. At the ports a pop
// always follows a leaf but the first (pops = leaves - 1), so only setup - pop, inner
// and leaf + pop are measurable; docs/rtl.md defines pop by the unit's states. The fit
// (least squares, rounded) uses the rays with pops = leaves - 1; every ray is then
// checked against the four constants.
struct TimingSample {
  std::uint64_t busy;
  std::uint32_t inner, leaves, pops;
};

std::optional<std::array<std::int64_t, 3>> fit_timing(const std::vector<TimingSample>& samples) {
  double m[3][4] = {};
  for (const TimingSample& s : samples) {
    if (s.pops + 1 != s.leaves) continue;
    const double x[3] = {1.0, double(s.inner), double(s.leaves)};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += x[i] * x[j];
      m[i][3] += x[i] * double(s.busy);
    }
  }
  for (int c = 0; c < 3; ++c) {
    int p = c;
    for (int r = c + 1; r < 3; ++r) {
      if (std::abs(m[r][c]) > std::abs(m[p][c])) p = r;
    }
    if (std::abs(m[p][c]) < 1e-6) return std::nullopt;
    std::swap(m[c], m[p]);
    for (int r = 0; r < 3; ++r) {
      if (r == c) continue;
      const double f = m[r][c] / m[c][c];
      for (int k = c; k < 4; ++k) m[r][k] -= f * m[c][k];
    }
  }
  std::array<std::int64_t, 3> k;
  for (int i = 0; i < 3; ++i) k[i] = std::llround(m[i][3] / m[i][i]);
  return k;
}

// The netlist testbench's input (sim/rpu_tu_netlist_tb.sv), hex words, each stream as
// its words (word 0 first) so that the testbench knows no field but the memory port's:
// a header (image words, rays, IU tests), the tu_cfg, the image (little-endian words);
// per ray the tu_req (tag = the ray's index), its number of IU tests, the tu_rsp
// expected and the bits of it compared (expected_of); per IU test in walk order the
// iu_req expected, the bits of it compared (tag, the ray, t_best, record) and the iu_rsp to
// answer with (the Tracer's; random t, u, v on a miss). Rays the Tracer ends with a
// stack overflow are left out (the counters are all that is defined).
// Which of n rays end their packets: packets of --packet in order, as a chunk's trace
// sends them; one in eight ends early, so packets of every size up to it arrive.
std::vector<bool> packet_ends_of(std::size_t n, const Options& o) {
  std::vector<bool> ends(n);
  std::mt19937_64 rng(o.seed ^ 0x7061636b6574ULL);
  int size = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ++size;
    ends[i] = size == o.packet || i + 1 == n || rng() % 8 == 0;
    if (ends[i]) size = 0;
  }
  return ends;
}

int write_vectors(const Options& o, const functional::SceneImage& si, const functional::Tracer& tracer,
                  const std::vector<Case>& cases) {
  const std::vector<std::uint8_t>& image = si.image.bytes;
  constexpr std::size_t kLineWords = streams::kMemLineBytes / 4;
  std::vector<std::uint32_t> words((image.size() + streams::kMemLineBytes - 1) / streams::kMemLineBytes * kLineWords, 0);
  std::memcpy(words.data(), image.data(), image.size());
  std::vector<std::uint32_t> rays, tests;
  const auto append = [](std::vector<std::uint32_t>& v, const auto& stream_words) {
    v.insert(v.end(), stream_words.begin(), stream_words.end());
  };
  const std::uint32_t tag_mask = (1u << streams::kRayTagBits) - 1;
  std::mt19937_64 rng(o.seed);
  std::vector<functional::IuTest> walk;
  std::size_t count = 0, test_count = 0;
  const std::vector<bool> packet_ends = packet_ends_of(
      static_cast<std::size_t>(std::count_if(cases.begin(), cases.end(), [](const Case& c) { return !c.fault; })), o);
  for (const Case& c : cases) {
    if (c.fault) continue;
    walk.clear();
    tracer.trace(c.ray, c.mode, walk);
    const std::uint32_t tag = static_cast<std::uint32_t>(count) & tag_mask;
    streams::TuReq req = request_of(c, tag);
    req.packet_end = packet_ends[count];
    append(rays, req.pack());
    rays.push_back(static_cast<std::uint32_t>(walk.size()));
    const Expected want = expected_of(c, tag);
    append(rays, want.rsp.pack());
    append(rays, want.care.pack());
    for (const functional::IuTest& t : walk) {
      // Compared: the tag, the ray in the format (rpu_tu_pipe's testbench finds a test's
      // ray by it), t_best, the record; the watertight set-up in that mode.
      const streams::IuReq q = iu_request_of(t, tag);
      streams::IuReq care;
      constexpr std::uint32_t kAllBits = ~std::uint32_t{0};
      care.tag = care.t_min = care.t_best = kAllBits;
      care.origin.fill(kAllBits);
      care.direction.fill(kAllBits);
      care.record.fill(kAllBits);
      if (o.isect == "watertight") care.kx = care.ky = care.kz = care.shear_x = care.shear_y = kAllBits;
      streams::IuRsp r{tag, std::uint32_t{t.hit}, t.result.t, t.result.u, t.result.v};
      if (!t.hit) {  // a miss carries random t, u, v: the unit must ignore them
        r.t = static_cast<std::uint32_t>(rng());
        r.u = static_cast<std::uint32_t>(rng());
        r.v = static_cast<std::uint32_t>(rng());
      }
      append(tests, q.pack());
      append(tests, care.pack());
      append(tests, r.pack());
      ++test_count;
    }
    ++count;
  }
  OutputFile file(o.write_vectors);
  std::ostream& out = file.stream();
  out << words.size() << " " << count << " " << test_count << "\n";
  char word[16];
  const auto put = [&](const auto& v, std::size_t per_line) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::snprintf(word, sizeof word, "%08" PRIx32 "%c", v[i], (i + 1) % per_line == 0 ? '\n' : ' ');
      out << word;
    }
  };
  put(tu_config(si.layout).pack(), streams::TuCfg::kWords);
  put(words, kLineWords);
  put(rays, streams::TuReq::kWords + 1 + 2 * streams::TuRsp::kWords);
  put(tests, 2 * streams::IuReq::kWords + streams::IuRsp::kWords);
  file.commit();
  std::printf("tu_cosim: wrote %zu rays (%zu IU tests) and a %zu-byte image to %s\n", count, test_count,
              image.size(), o.write_vectors.c_str());
  return 0;
}

// The scene with its geometry, camera and lights times 2^k, exactly: the rays made
// from it scale too, and the image's kd space moves by k.
Scene scaled(Scene scene, int k) {
  const float s = std::ldexp(1.0f, k);
  for (glm::vec3& p : scene.positions) p *= s;
  const double d = std::ldexp(1.0, k);
  scene.camera.position *= d;
  scene.camera.look_at *= d;
  scene.camera.focus_distance *= d;
  for (Light& l : scene.lights) {
    l.position *= d;
    l.edge_u *= d;
    l.edge_v *= d;
  }
  return scene;
}

// The harness's memory as the cycle model's walk sees it: one line asked a cycle, each
// answered `latency` cycles later, in order, one answer a cycle; the unit steps on the
// cycle after the last answer. Nothing lies between it and the unit, where the chip has
// memory_wait cycles of registers before its caches, so its lines are back that much
// earlier.
class HarnessLines final : public cycle::LineSource {
 public:
  HarnessLines(cycle::Cycle latency, cycle::Cycle registers) : latency_(latency), registers_(registers) {}
  cycle::Cycle read(cycle::Cycle now, std::uint32_t address, std::uint32_t bytes, bool) override {
    const std::uint32_t first = address / streams::kMemLineBytes;
    const std::uint32_t last = (address + bytes - 1) / streams::kMemLineBytes;
    cycle::Cycle back = now;
    for (std::uint32_t line = first; line <= last; ++line) {
      const cycle::Cycle asked = std::max(now, port_free_);
      port_free_ = asked + 1;
      back = std::max(asked + latency_, answer_free_);
      answer_free_ = back + 1;
    }
    return back + 1 - std::min(back + 1 - now, registers_);
  }

 private:
  cycle::Cycle latency_, registers_, port_free_ = 0, answer_free_ = 0;
};

// The cycles the cycle model's ray unit (`slots` slots, one IU) takes for the cases in
// order, each slot taking the next ray as it answers one (the harness keeps more in
// flight than there are slots).
cycle::Cycle model_cycles(const std::vector<Case>& cases, const cycle::WalkCosts& costs, int slots,
                          cycle::Cycle mem_latency) {
  HarnessLines lines(mem_latency, costs.memory_wait);
  std::vector<cycle::IuTimer> ius(1);
  struct Slot {
    std::size_t ray = 0;
    cycle::Walk walk;
    cycle::TraversalUnitTime time;
  };
  std::vector<Slot> slot(static_cast<std::size_t>(slots));
  using Event = std::pair<cycle::Cycle, std::size_t>;
  std::priority_queue<Event, std::vector<Event>, std::greater<>> events;
  std::size_t next = 0;
  for (std::size_t s = 0; s < slot.size() && next < cases.size(); ++s) {
    slot[s].ray = next++;
    events.push({0, s});
  }
  cycle::Cycle end = 0;
  while (!events.empty()) {
    const auto [now, s] = events.top();
    events.pop();
    Slot& sl = slot[s];
    const cycle::WalkStep step = cycle::step_walk(cases[sl.ray].log, sl.walk, now, costs, lines, ius, sl.time);
    if (!step.done) {
      events.push({step.next, s});
      continue;
    }
    end = std::max(end, now);
    if (next < cases.size()) {
      sl = Slot{next++, {}, {}};
      events.push({now + costs.turnaround, s});
    }
  }
  return end;
}

// --mem-spread: a line's extra delay, 0 to `spread` cycles, a hash of its address, so
// that lines asked later may be answered first; the same for the RTL and the model.
std::uint64_t address_delay(std::uint32_t addr, int spread) {
  if (spread <= 0) return 0;
  const std::uint32_t line = addr / streams::kMemLineBytes;
  return ((line * 2654435761u) >> 13) % static_cast<std::uint32_t>(spread + 1);
}

// The harness's memory with no stalls or jitter: a line is answered `latency` cycles
// plus its address's delay after it is asked for (the pipelined unit asks one a cycle
// at most; the harness answers the one back first, the oldest of those back together).
class HarnessPipeLines final : public cycle::LineSource {
 public:
  HarnessPipeLines(cycle::Cycle latency, int spread) : latency_(latency), spread_(spread) {}
  cycle::Cycle read(cycle::Cycle now, std::uint32_t address, std::uint32_t, bool) override {
    return now + latency_ + address_delay(address, spread_);
  }

 private:
  cycle::Cycle latency_;
  int spread_;
};

// A packet's walk as the golden model makes it, for the cycle model's unit.
class CaseWalks final : public cycle::PacketWalks {
 public:
  CaseWalks(const std::vector<Case>& cases, const functional::Tracer& tracer) : cases_(cases), tracer_(tracer) {}
  void walk(std::span<const std::uint32_t> rays, functional::TraceLog& log) override {
    packet_.clear();
    for (const std::uint32_t i : rays) packet_.push_back(cases_[i].ray);
    out_.resize(packet_.size());
    tracer_.trace_packet(packet_, cases_[rays[0]].mode, out_, log);
  }

 private:
  const std::vector<Case>& cases_;
  const functional::Tracer& tracer_;
  std::vector<TraceRay> packet_;
  std::vector<TraceHit> out_;
};

// The cycles the cycle model's pipelined unit (one IU) takes for the cases, offered in
// order with at most `in_flight` in the unit, as the harness offers them; with packets,
// ended where `packet_ends` says.
cycle::Cycle model_pipe_cycles(const std::vector<Case>& cases, const cycle::PipeCosts& costs, int in_flight,
                               cycle::Cycle mem_latency, int mem_spread, const functional::Tracer& tracer,
                               const std::vector<bool>& packet_ends, std::uint64_t& node_fetches) {
  HarnessPipeLines lines(mem_latency, mem_spread);
  std::vector<cycle::IuTimer> ius(1);
  CaseWalks walks(cases, tracer);
  cycle::PipeTraversalUnit unit(costs, lines, ius, &walks);
  std::vector<std::uint32_t> answered;
  std::size_t next = 0, done = 0, inside = 0;
  cycle::Cycle now = 0, progress = 0;
  for (; done < cases.size(); ++now) {
    if (next < cases.size() && inside < static_cast<std::size_t>(in_flight) && unit.ready()) {
      const Case& c = cases[next];
      unit.take(static_cast<std::uint32_t>(next), c.log,
                {packet_ends[next], tracer.direction_signs(c.ray), c.mode == TraceMode::kAny});
      ++next;
      ++inside;
    }
    answered.clear();
    unit.tick(now, answered);
    inside -= answered.size();
    done += answered.size();
    if (!answered.empty()) progress = now;
    if (now - progress > 1000000) throw Error("tu_cosim: the cycle model's pipelined unit answered nothing for 10^6 cycles");
  }
  node_fetches = unit.time.inner + unit.time.leaves;
  return now;
}

// `model` outlives the run, so that its waveforms are kept whether the run passed or
// failed.
int run(const Options& o, std::unique_ptr<Model<harness::Tu>>& model) {
  const fp::Format format = fp::format_by_name(o.format);
  const bool watertight = o.isect == "watertight";
  const Scene scene = scaled(resolve_scene(o.scene), o.scale);
  // The RTL's StackDepth is the default configuration's (rpu_tu.sv).
  KdBuildConfig build = kd_build_config_for("default");
  build.format = format;
  const functional::SceneImage si =
      functional::make_scene_image(scene, build, watertight ? IsectMode::kWatertight : IsectMode::kWoop);
  const std::vector<std::uint8_t>& image = si.image.bytes;
  const functional::Tracer tracer(image, si.layout, format, build.stack_depth, false);

  // The rays and their expected results.
  const int side = static_cast<int>(std::ceil(std::sqrt(double(o.rays))));
  std::vector<TraceRay> camera = test::camera_rays(scene, side, side);
  camera.resize(static_cast<std::size_t>(o.rays));
  const std::vector<TraceRay> random = test::random_rays(scene, o.rays, static_cast<std::uint32_t>(o.seed) + 41);
  const std::vector<TraceRay> shadow = shadow_rays(scene, camera, tracer, o.rays);
  const std::vector<TraceRay> plane = test::split_plane_rays(si, o.plane_rays < 0 ? (o.rays + 9) / 10 : o.plane_rays,
                                                             static_cast<std::uint32_t>(o.seed) + 43);
  std::vector<Case> cases;
  for (const TraceRay& r : camera) cases.push_back({r, Kind::kCamera, TraceMode::kClosest, {}});
  for (const TraceRay& r : random) cases.push_back({r, Kind::kRandom, TraceMode::kClosest, {}});
  for (const TraceRay& r : shadow) cases.push_back({r, Kind::kShadow, TraceMode::kAny, {}});
  for (std::size_t i = 0; i < plane.size(); ++i) {
    cases.push_back({plane[i], Kind::kPlane, i % 2 ? TraceMode::kAny : TraceMode::kClosest, {}});
  }
  for (Case& c : cases) {
    try {
      c.expect = tracer.trace(c.ray, c.mode, c.log);
      c.pops = static_cast<std::uint32_t>(std::count_if(c.log.events.begin(), c.log.events.end(), [](const auto& e) {
        return e.kind == functional::TraceEvent::Kind::kPop;
      }));
    } catch (const Error&) {
      c.fault = true;
    }
  }

  if (!o.write_vectors.empty()) return write_vectors(o, si, tracer, cases);

  const std::string slots = std::to_string(o.slots);
  const ModelInfo* info = find_model<harness::Tu>({{"format", o.format}, {"isect", o.isect},
                                                   {"with_iu", o.with_iu ? "1" : "0"}, {"slots", slots},
                                                   {"pipe", o.pipe ? "1" : "0"},
                                                   {"packet", std::to_string(o.packet)}});
  if (!info) {
    std::fprintf(stderr, "tu_cosim: no model with format=%s isect=%s with_iu=%d slots=%d pipe=%d packet=%d in this "
                 "build; built: %s\n", o.format.c_str(), o.isect.c_str(), o.with_iu ? 1 : 0, o.slots, o.pipe ? 1 : 0,
                 o.packet, built_models<harness::Tu>().c_str());
    return 2;
  }
  model = make_model<harness::Tu>(*info, o.seed, o.trace);
  const int setups = info->number("setups");  // the built pipelined unit's set-up engines
  const int line_tag_bits = info->number("line_tag_bits");  // ... and its line table's tag bits
  // The TU alone leaves its IU port to the harness's C++ IU; the ray unit has its own.
  const bool iu_port = !o.with_iu;

  Stalls stalled(o.seed, o.stall);
  const std::vector<bool> packet_ends = packet_ends_of(cases.size(), o);
  std::mt19937_64& rng = stalled.rng();  // also the agents' delays and the IU's junk on a miss
  const functional::SoftArith ar{format};
  // The agents: the memory answers a line after its latency plus a random delay, in
  // order to a walker, by tag in any order to a pipelined unit (one whose delay is past
  // first); the C++ IU tests likewise.
  struct Owed {
    std::uint64_t ready;
    std::uint32_t addr, tag;
    streams::IuRsp iu;
  };
  std::deque<Owed> mem_q, iu_q;
  std::size_t mem_pick = 0, iu_pick = 0;    // the answers presented
  bool mem_presented = false, iu_presented = false;  // ... and not taken last cycle
  // A due answer, picked at random while several are due (or without jitter, the one
  // due first, the oldest of those due together, as the cycle model takes them), kept
  // until taken (a valid stream holds its payload).
  const auto pick_due = [&rng](const std::deque<Owed>& q, bool any_order, bool at_random,
                               std::uint64_t now) -> std::size_t {
    if (!any_order) return 0;
    std::vector<std::size_t> due;
    for (std::size_t i = 0; i < q.size(); ++i) {
      if (q[i].ready <= now) due.push_back(i);
    }
    if (due.size() < 2) return due.empty() ? 0 : due.front();
    if (!at_random) {
      return *std::min_element(due.begin(), due.end(), [&q](std::size_t a, std::size_t b) {
        return q[a].ready < q[b].ready || (q[a].ready == q[b].ready && a < b);
      });
    }
    return due[std::uniform_int_distribution<std::size_t>(0, due.size() - 1)(rng)];
  };
  std::uint64_t mem_last = 0, iu_last = 0;
  const std::uint32_t tag_mask = (1u << streams::kRayTagBits) - 1;

  harness::Tu::Inputs in;
  in.cfg = tu_config(si.layout);
  Clock clock(*model);
  clock.reset(in);

  std::vector<TimingSample> samples;
  std::map<std::uint64_t, std::uint64_t> miss_busy;  // busy cycles of rays that fetch nothing
  PendingByTag<std::size_t> pending("tu_req", "tu_rsp", streams::kRayTagBits);  // the case of each ray in flight
  Watchdog watchdog(1000000);
  std::size_t next = 0, done = 0;
  bool responded = false;
  std::uint64_t busy = 0, cycles = 0, lines = 0, node_lines = 0;
  const auto begin = std::chrono::steady_clock::now();
  auto fail = [&](const std::string& what) {
    std::printf("tu_cosim FAIL: %s, format %s, %s test, cycle %" PRIu64 "\n  %s\n", o.scene.c_str(),
                o.format.c_str(), o.isect.c_str(), clock.cycle(), what.c_str());
    return 1;
  };

  try {
    while (done < cases.size()) {
      const std::uint64_t cycle = clock.cycle();
      // Up to --in-flight rays at once; with one, the busy cycles below are the ray's.
      const bool in_flight = !pending.empty();
      const bool full = pending.size() >= static_cast<std::size_t>(o.in_flight);
      const Case* current = in_flight ? &cases[pending.oldest()] : next < cases.size() ? &cases[next] : nullptr;
      in.req_valid = !full && next < cases.size() && !stalled();
      if (in.req_valid) {
        in.req = request_of(cases[next], static_cast<std::uint32_t>(next) & tag_mask);
        in.req.packet_end = packet_ends[next];
      }
      in.rsp_ready = !stalled();
      in.mem_req_ready = !stalled();
      if (!mem_presented) mem_pick = pick_due(mem_q, o.pipe, o.mem_jitter > 0, cycle);
      in.mem_rsp_valid = !mem_q.empty() && (mem_presented || mem_q[mem_pick].ready <= cycle) && !stalled();
      if (in.mem_rsp_valid) {
        in.mem_rsp.tag = mem_q[mem_pick].tag;
        std::memcpy(in.mem_rsp.data.data(), image.data() + mem_q[mem_pick].addr, streams::kMemLineBytes);
      }
      in.iu_req_ready = !stalled();
      // With several rays in flight the IU answers in any order.
      if (!iu_presented) iu_pick = pick_due(iu_q, o.in_flight > 1, true, cycle);
      in.iu_rsp_valid = !iu_q.empty() && (iu_presented || iu_q[iu_pick].ready <= cycle) && !stalled();
      if (in.iu_rsp_valid) in.iu_rsp = iu_q[iu_pick].iu;

      const harness::Tu::Outputs out = clock.settle(in);

      // Cycles the unit spends waiting: a request presented or a response owed.
      const bool waiting = out.mem_req_valid || !mem_q.empty() || out.iu_req_valid || !iu_q.empty();
      if (o.in_flight == 1 && in_flight && !responded) {
        if (out.rsp_valid) {
          responded = true;
        } else if (!waiting) {
          ++busy;
        }
      }

      if (in.req_valid && out.req_ready) {
        pending.add(in.req.tag, next);
        responded = false;
        busy = 0;
        ++next;
        watchdog.progress(cycle);
      }
      if (out.rsp_valid && in.rsp_ready) {
        const std::size_t i = pending.take(out.rsp.tag);
        const Case& c = cases[i];
        const Expected want = expected_of(c, static_cast<std::uint32_t>(i) & tag_mask);
        const std::string mismatch = field_mismatch(want.rsp, out.rsp, want.care);
        if (!mismatch.empty()) return fail("ray " + std::to_string(i) + ": " + describe_ray(c) + "\n  " + mismatch);
        if (!c.fault && o.in_flight == 1) {
          if (c.expect.counters.nodes == 0) {
            ++miss_busy[busy];
          } else {
            const auto& n = c.expect.counters;
            samples.push_back({busy, n.nodes - n.leaves, n.leaves, c.pops});
          }
        }
        ++done;
        watchdog.progress(cycle);
      }
      if (out.mem_req_valid && in.mem_req_ready) {
        ++lines;
        const std::uint32_t addr = out.mem_req.addr;
        node_lines += addr - si.layout.kd_nodes.offset < si.layout.kd_nodes.bytes;
        if (addr % streams::kMemLineBytes != 0 || std::uint64_t{addr} + streams::kMemLineBytes > image.size()) {
          char what[96];
          std::snprintf(what, sizeof what, "memory request at 0x%08x: unaligned or outside the %zu-byte image", addr,
                        image.size());
          return fail(std::string(what) + "; ray " + describe_ray(*current));
        }
        const std::uint64_t ready = cycle + static_cast<std::uint64_t>(o.mem_latency) +
                                    address_delay(addr, o.pipe ? o.mem_spread : 0) +
                                    static_cast<std::uint64_t>(std::uniform_int_distribution<int>(0, o.mem_jitter)(rng));
        mem_last = o.pipe ? ready : std::max(mem_last, ready);
        mem_q.push_back({mem_last, addr, out.mem_req.tag, {}});
      }
      mem_presented = in.mem_rsp_valid && !out.mem_rsp_ready;
      if (in.mem_rsp_valid && out.mem_rsp_ready) mem_q.erase(mem_q.begin() + static_cast<std::ptrdiff_t>(mem_pick));
      if (iu_port) {
        if (out.iu_req_valid && in.iu_req_ready) {
          iu_last = std::max(iu_last, cycle + static_cast<std::uint64_t>(o.iu_latency) +
                                          std::uniform_int_distribution<int>(0, o.iu_jitter)(rng));
          iu_q.push_back({iu_last, 0, 0, iu_answer(ar, watertight, out.iu_req, rng)});
        }
        iu_presented = in.iu_rsp_valid && !out.iu_rsp_ready;
        if (in.iu_rsp_valid && out.iu_rsp_ready) iu_q.erase(iu_q.begin() + static_cast<std::ptrdiff_t>(iu_pick));
      }
      watchdog.check(cycle, !pending.empty(), [&] { return describe_ray(cases[pending.oldest()]); });
      clock.tick();
    }
    // Every line and IU answer owed was taken, and nothing moves afterwards.
    if (!mem_q.empty() || !iu_q.empty()) {
      return fail(std::to_string(mem_q.size()) + " memory and " + std::to_string(iu_q.size()) +
                  " IU responses never taken after the last ray");
    }
    harness::Tu::Inputs idle = in;
    idle.req_valid = idle.mem_rsp_valid = idle.iu_rsp_valid = false;
    idle.rsp_ready = idle.mem_req_ready = idle.iu_req_ready = true;
    cycles = clock.cycle();  // the run's, without the quiet cycles below
    expect_quiet(clock, idle, 64, [iu_port](const harness::Tu::Outputs& out) {
      return out.rsp_valid       ? "a tu_rsp (tag " + hex(out.rsp.tag, streams::kRayTagBits) + ")"
             : out.mem_req_valid ? "a mem_req (addr " + hex(out.mem_req.addr, 32) + ")"
             : iu_port && out.iu_req_valid ? "an iu_req (tag " + hex(out.iu_req.tag, streams::kRayTagBits) + ")"
                                           : std::string();
    });
  } catch (const CosimFailure& e) {
    return fail(e.what());
  }
  const std::uint64_t cycle = cycles;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();

  std::size_t hits = 0;
  std::uint64_t nodes = 0, tests = 0;
  for (const Case& c : cases) {
    hits += c.expect.hit;
    nodes += c.expect.counters.nodes;
    tests += c.expect.counters.tests;
  }
  std::printf("tu_cosim ok: %s, format %s, %s test%s: %zu rays (%d camera, %d random, %zu shadow, "
              "%zu split-plane; %zu hit) "
              "bit for bit; %" PRIu64 " cycles in %.1f s (%.0f cycles/s, %.0f rays/s)\n",
              o.scene.c_str(), o.format.c_str(), o.isect.c_str(), o.with_iu ? ", RTL IU" : ", C++ IU", cases.size(),
              o.rays, o.rays, shadow.size(), plane.size(), hits, cycle, seconds, double(cycle) / seconds,
              double(cases.size()) / seconds);
  // The unit's throughput on this stream: kd nodes visited and triangles tested per
  // cycle, with --slots ray slots and --in-flight rays offered; and the memory port's
  // lines per cycle (one at most, fewer by the --stall share of cycles).
  std::printf("tu_cosim throughput: %d slots%s, %d rays in flight: %.4f node steps per cycle, %.4f IU tests per "
              "cycle, %.4f memory lines per cycle, %.1f cycles per ray\n",
              o.slots, o.pipe ? " (shared pipeline)" : "", o.in_flight, double(nodes) / double(cycle),
              double(tests) / double(cycle), double(lines) / double(cycle), double(cycle) / double(cases.size()));
  // A node line serves every ray of a packet that visits the node: fewer lines than the
  // rays' own walks visit nodes.
  std::printf("tu_cosim nodes: %" PRIu64 " node lines for %" PRIu64 " node visits (%.3f a visit, packets of %d)\n",
              node_lines, nodes, double(node_lines) / double(std::max<std::uint64_t>(nodes, 1)), o.packet);
  if (o.packet > 1 && nodes > 0 && node_lines >= nodes) {
    return fail("packets of " + std::to_string(o.packet) + " shared no node line: " + std::to_string(node_lines) +
                " lines for " + std::to_string(nodes) + " node visits");
  }

  if (!o.cycle_model.empty()) {
    const spec::HardwareConfig* config = nullptr;
    for (const spec::HardwareConfig& c : spec::kConfigs) {
      if (c.name == o.cycle_model) config = &c;
    }
    const cycle::WalkCosts costs =
        cycle::WalkCosts::of(*config, watertight ? IsectMode::kWatertight : IsectMode::kWoop);
    cycle::Cycle modelled = 0;
    std::uint64_t model_node_lines = node_lines;
    if (o.pipe) {
      cycle::PipeCosts pipe = cycle::PipeCosts::of(*config, watertight ? IsectMode::kWatertight : IsectMode::kWoop);
      pipe.slots = static_cast<std::uint32_t>(o.slots);
      pipe.setups = static_cast<std::uint32_t>(setups);
      pipe.memory_wait = 0;  // the harness answers the unit's port directly, by tag,
      pipe.by_tag = true;    // with the lines in flight the built unit's table holds
      pipe.lines = 1u << line_tag_bits;
      pipe.packet = static_cast<std::uint32_t>(o.packet);
      modelled = model_pipe_cycles(cases, pipe, o.in_flight, static_cast<cycle::Cycle>(o.mem_latency), o.mem_spread,
                                   tracer, packet_ends, model_node_lines);
    } else {
      modelled = model_cycles(cases, costs, o.slots, static_cast<cycle::Cycle>(o.mem_latency));
    }
    const double error = 100.0 * (double(modelled) - double(cycle)) / double(cycle);
    std::printf("tu_cosim cycle model: '%s' step cycles, %d slots: %" PRIu64 " cycles against the RTL's %" PRIu64
                " (%+.2f%%)\n",
                o.cycle_model.c_str(), o.slots, modelled, cycle, error);
    // The same packets walk the same nodes: the RTL's node lines are the golden walks'.
    if (model_node_lines != node_lines) {
      std::printf("tu_cosim FAIL: the cycle model's packets fetch %" PRIu64 " node lines, the RTL's %" PRIu64 "\n",
                  model_node_lines, node_lines);
      return 1;
    }
    if (std::abs(error) > o.cycle_tolerance) {
      std::printf("tu_cosim FAIL: the cycle model is %.2f%% off the RTL, more than --cycle-tolerance %.2f%%\n", error,
                  o.cycle_tolerance);
      return 1;
    }
  }

  std::string misses;
  for (const auto& [b, n] : miss_busy) misses += " " + std::to_string(b) + " (" + std::to_string(n) + " rays)";
  if (o.timing) {
    const auto k = fit_timing(samples);
    if (!k) {
      std::printf("tu_cosim: too few walking rays to measure the step cycles\n");
      return 1;
    }
    std::size_t fit = 0, used = 0;
    for (const TimingSample& s : samples) {
      if (s.pops + 1 != s.leaves) continue;
      ++used;
      fit += static_cast<std::int64_t>(s.busy) == (*k)[0] + (*k)[1] * s.inner + (*k)[2] * s.leaves;
    }
    std::printf("tu_cosim timing: setup - pop %" PRId64 ", inner %" PRId64 ", leaf + pop %" PRId64
                " cycles besides memory and IU waits (fits %zu of %zu walking rays with pops = leaves - 1, of %zu); "
                "rays that fetch nothing:%s\n",
                (*k)[0], (*k)[1], (*k)[2], fit, used, samples.size(), misses.c_str());
    if (fit != used) {
      std::printf("tu_cosim FAIL: the step cycles are not fixed per step kind\n");
      return 1;
    }
  }
  if (!o.expect_timing.empty()) {
    std::array<std::int64_t, 4> k{};
    if (std::sscanf(o.expect_timing.c_str(), "%" SCNd64 ",%" SCNd64 ",%" SCNd64 ",%" SCNd64, &k[0], &k[1], &k[2],
                    &k[3]) != 4) {
      std::fprintf(stderr, "tu_cosim: --expect-timing wants setup,inner,leaf,pop\n");
      return 2;
    }
    for (const TimingSample& s : samples) {
      const std::int64_t expected = k[0] + k[1] * s.inner + k[2] * s.leaves + k[3] * s.pops;
      if (static_cast<std::int64_t>(s.busy) != expected) {
        std::printf("tu_cosim FAIL: a ray with %u inner nodes, %u leaves and %u pops spent %" PRIu64
                    " cycles besides memory and IU waits; spec/latencies.toml [tu.<format>] (setup,inner,leaf,pop = %s) "
                    "gives %" PRId64 " (measure with --timing; docs/rtl.md)\n",
                    s.inner, s.leaves, s.pops, s.busy, o.expect_timing.c_str(), expected);
        return 1;
      }
    }
    std::printf("tu_cosim timing ok: every one of %zu walking rays spends setup + inner * %" PRId64 " + leaf * %" PRId64
                " + pop * %" PRId64 " (setup %" PRId64 ") cycles besides memory and IU waits\n",
                samples.size(), k[1], k[2], k[3], k[0]);
  }
  return 0;
}

}  // namespace
}  // namespace rpu::sim

int main(int argc, char** argv) {
  rpu::sim::Options o;
  CLI::App app{"Ray-level co-simulation of the RTL traversal unit against the golden tracer"};
  app.add_option("--scene", o.scene, "scene name or file (rpu scenes)");
  app.add_option("--format", o.format, "number format (spec/formats.toml)");
  app.add_option("--isect", o.isect, "intersection test")->check(CLI::IsMember({"woop", "watertight"}));
  app.add_flag("--with-iu", o.with_iu, "the RTL IU inside (rpu_ray_unit), else the C++ IU answers");
  app.add_option("--slots", o.slots, "the TU's ray slots (a model built with them)")->check(CLI::Range(1, 256));
  app.add_flag("--pipe", o.pipe, "the slots share a node-step pipeline (rpu_tu_pipe; a model built so)");
  app.add_option("--packet", o.packet, "with --pipe: rays a slot walks together (a model built so)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  app.add_option("--in-flight", o.in_flight, "rays in the unit at once (1: step cycles are measured per ray)")
      ->check(CLI::Range(1, 256));
  app.add_option("--scale", o.scale, "scale the scene by 2^K (its kd scale exponent moves by K)")
      ->check(CLI::Range(-100, 100));
  app.add_option("--rays", o.rays, "rays of each kind (camera, random, shadow)")->check(CLI::PositiveNumber);
  app.add_option("--plane-rays", o.plane_rays, "rays from origins on split planes (default: a tenth of --rays)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", o.seed, "seed of stalls, delays and the model's initial values");
  app.add_option("--mem-latency", o.mem_latency, "memory latency in cycles")->check(CLI::NonNegativeNumber);
  app.add_option("--mem-jitter", o.mem_jitter, "random extra memory delay, up to")->check(CLI::NonNegativeNumber);
  app.add_option("--mem-spread", o.mem_spread,
                 "with --pipe: a line's extra delay by its address, up to (answers out of request order, the same "
                 "for the cycle model)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--iu-latency", o.iu_latency, "C++ IU latency in cycles")->check(CLI::NonNegativeNumber);
  app.add_option("--iu-jitter", o.iu_jitter, "random extra IU delay, up to")->check(CLI::NonNegativeNumber);
  app.add_option("--stall", o.stall, "probability a port stalls in a cycle")->check(CLI::Range(0.0, 0.9));
  app.add_flag("--timing", o.timing, "print the measured step cycles");
  app.add_option("--expect-timing", o.expect_timing, "setup,inner,leaf,pop the RTL must measure");
  app.add_option("--trace", o.trace, "write an FST waveform to this file");
  app.add_option("--write-vectors", o.write_vectors, "write the rays, results and image for the netlist testbench");
  app.add_option("--cycle-model", o.cycle_model,
                 "time the same rays with the cycle model's ray unit at this named configuration's step cycles "
                 "(its format the --format; --with-iu, no stalls or jitter) and compare the cycles");
  app.add_option("--cycle-tolerance", o.cycle_tolerance, "percent the cycle model may be off the RTL")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  if (!o.cycle_model.empty()) {
    const rpu::spec::HardwareConfig* config = nullptr;
    for (const rpu::spec::HardwareConfig& c : rpu::spec::kConfigs) {
      if (c.name == o.cycle_model) config = &c;
    }
    if (!config || config->format != o.format) {
      std::fprintf(stderr, "tu_cosim: --cycle-model wants a named configuration in --format %s (spec/configs.toml)\n",
                   o.format.c_str());
      return 2;
    }
    if (!o.with_iu || o.stall != 0 || o.mem_jitter != 0) {
      std::fprintf(stderr, "tu_cosim: --cycle-model times the ray unit: --with-iu --stall 0 --mem-jitter 0\n");
      return 2;
    }
  }
  if (o.packet > 1 && !o.pipe) {
    std::fprintf(stderr, "tu_cosim: --packet walks packets in a pipelined unit (--pipe)\n");
    return 2;
  }
  if (o.in_flight > 1 && (o.timing || !o.expect_timing.empty())) {
    std::fprintf(stderr, "tu_cosim: --timing and --expect-timing measure one ray at a time (--in-flight 1)\n");
    return 2;
  }
  rpu::report_sigbus_as_write_failure("tu_cosim");
  try {
    rpu::sim::check_output_paths(o.trace, o.write_vectors);
    std::unique_ptr<rpu::sim::Model<rpu::sim::harness::Tu>> model;
    const int status = rpu::sim::run(o, model);
    if (model) model->close_trace();
    return status;
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "tu_cosim: %s\n", e.what());
    return 2;
  }
}
