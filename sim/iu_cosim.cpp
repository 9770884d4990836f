// Co-simulation of the RTL intersection unit (rtl/rpu_iu.sv) against the functional
// model (docs/rtl.md, "Intersection unit"). The golden tracer traces camera, random and
// shadow rays (any-hit, toward a light) over each scene with SoftArith in the format and
// reports every IU test of each walk: the ray registers, the record as read from the
// memory image, t_best and the result. Each test goes through the unit's valid/ready
// port with random stalls on both sides; responses are paired with their request by tag
// and hit, t, u, v compared bit for bit. The first mismatch stops the run and prints
// the inputs, both outputs and the cycle.
//
//   iu_cosim --format fp32 --isect woop --scene cornell [--scene ...] [--rays N] [--seed S]
//            [--trace FILE.fst] [--check-config] [--write-vectors FILE --vectors N]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "cosim_core.hpp"
#include "fp/format.hpp"
#include "fp/soft.hpp"
#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "harness_outputs.hpp"
#include "iu_test_request.hpp"
#include "model.hpp"
#include "rpu/harness/iu.hpp"
#include "rpu/spec.hpp"
#include "scene/geometry.hpp"
#include "scene/resolve.hpp"
#include "trace_fixtures.hpp"

namespace rpu::sim {
namespace {

using functional::IuTest;
using functional::TraceHit;
using functional::TraceMode;
using functional::TraceRay;

struct Options {
  std::string format, isect, trace, write_vectors;
  std::vector<std::string> scenes;
  int rays = 1000;  // per kind and scene
  std::int64_t vectors = 10000;
  std::uint64_t seed = 1;
  unsigned stall_percent = 6;
  bool check_config = false;
  double min_tests_per_cycle = 0;  // of the full-rate burst
};

// One IU test and where it came from, for the failure report.
struct Transaction {
  IuTest test;
  std::string where;
};

// Camera, random and shadow rays of one scene, traced by the golden model; every IU test
// of every walk becomes a transaction, in walk order.
class TransactionSource {
 public:
  TransactionSource(const Options& o, fp::Format f, IsectMode mode) : options_(o), format_(f), mode_(mode) {}

  // Appends the next ray's tests to `out`; false when every scene is done.
  bool next(std::deque<Transaction>& out) {
    while (true) {
      if (!tracer_) {
        if (scene_index_ >= options_.scenes.size()) return false;
        load(options_.scenes[scene_index_]);
      }
      if (ray_index_ < rays_.size()) break;
      if (kind_ == 0) {  // camera rays done: their shadow rays next
        rays_ = std::move(shadow_);
        shadow_.clear();
        kind_ = 1;
      } else if (kind_ == 1) {
        rays_ = test::random_rays(scene_.scene, options_.rays, static_cast<std::uint32_t>(options_.seed));
        kind_ = 2;
      } else {
        tracer_.reset();
        ++scene_index_;
        continue;
      }
      ray_index_ = 0;
    }
    const TraceRay& ray = rays_[ray_index_];
    const TraceMode mode = kind_ == 1 ? TraceMode::kAny : TraceMode::kClosest;
    const TraceHit hit = tracer_->trace(ray, mode, tests_);
    if (kind_ == 0 && hit.hit) shadow_.push_back(shadow_ray(ray, hit));
    static constexpr const char* kKinds[] = {"camera", "shadow", "random"};
    for (std::size_t k = 0; k < tests_.size(); ++k) {
      char where[160];
      std::snprintf(where, sizeof where, "scene %s, %s ray %zu, IU test %zu of its walk",
                    options_.scenes[scene_index_].c_str(), kKinds[kind_], ray_index_, k);
      out.push_back({tests_[k], where});
    }
    ++rays_traced_;
    ++ray_index_;
    return true;
  }

  std::int64_t rays_traced() const { return rays_traced_; }

 private:
  void load(const std::string& name) {
    scene_.scene = resolve_scene(name);
    KdBuildConfig build;
    build.format = format_;
    scene_.image = functional::make_scene_image(scene_.scene, build, mode_);
    tracer_ = std::make_unique<functional::Tracer>(scene_.image.image.bytes, scene_.image.layout, format_,
                                                   build.stack_depth, false);
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(options_.rays))));
    rays_ = test::camera_rays(scene_.scene, side, side);
    rays_.resize(static_cast<std::size_t>(options_.rays));
    kind_ = 0;
    ray_index_ = 0;
    shadow_.clear();
    light_ = light_position(scene_.scene);
  }

  static glm::dvec3 light_position(const Scene& s) {
    const Bounds b = scene_bounds(s);
    for (const Light& l : s.lights) {
      if (l.kind == LightKind::kPoint) return l.position;
      if (l.kind == LightKind::kArea) return l.position + 0.5 * (l.edge_u + l.edge_v);
    }
    // No point or area light: a point above the scene's box.
    return 0.5 * (b.lo + b.hi) + glm::dvec3(0.0, b.hi.y - b.lo.y, 0.0);
  }

  // From the camera ray's hit toward the light, any hit in (1e-3, 1) of the segment.
  TraceRay shadow_ray(const TraceRay& r, const TraceHit& h) const {
    const glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.direction[0], r.direction[1], r.direction[2]);
    const glm::dvec3 p = o + static_cast<double>(h.t) * d;
    TraceRay s = test::make_ray(p, light_ - p, 1e-3f);
    s.t_max = 1.0f;
    return s;
  }

  const Options& options_;
  fp::Format format_;
  IsectMode mode_;
  struct {
    Scene scene;
    functional::SceneImage image;
  } scene_;
  std::unique_ptr<functional::Tracer> tracer_;
  std::vector<TraceRay> rays_, shadow_;
  std::vector<IuTest> tests_;
  glm::dvec3 light_{0.0};
  std::size_t scene_index_ = 0, ray_index_ = 0;
  int kind_ = 0;
  std::int64_t rays_traced_ = 0;
};

// What the unit must answer: the model's hit and, on a hit, t, u, v; zeros on a miss.
streams::IuRsp expected_of(const IuTest& t, std::uint32_t tag) {
  return {tag, std::uint32_t{t.hit}, t.hit ? t.result.t : 0, t.hit ? t.result.u : 0, t.hit ? t.result.v : 0};
}

std::string value(fp::Format f, std::uint32_t bits) {
  char text[64];
  std::snprintf(text, sizeof text, "0x%0*" PRIx32 " (%.9g)", (f.width() + 3) / 4, bits,
                std::bit_cast<float>(fp::soft::to_fp32(f, bits & f.all_bits())));
  return text;
}

// The failure (`what`: the field report or a harness-core message), the test's inputs
// with their values in the format, and where the test came from.
void print_failure(const std::string& what, fp::Format f, std::uint64_t cycle, const Transaction& x) {
  const IuTest& t = x.test;
  std::fprintf(stderr, "iu cosim FAIL: at cycle %" PRIu64 ", %s, format %s: %s\n", cycle, x.where.c_str(),
               f.name().c_str(), what.c_str());
  for (int i = 0; i < 3; ++i) {
    std::fprintf(stderr, "  origin[%d] = %s  direction[%d] = %s\n", i, value(f, t.ray.origin[i]).c_str(), i,
                 value(f, t.ray.direction[i]).c_str());
  }
  std::fprintf(stderr, "  t_min = %s  t_best = %s\n", value(f, t.ray.t_min).c_str(), value(f, t.t_best).c_str());
  std::fprintf(stderr, "  kx ky kz = %d %d %d  shear = %s %s\n", t.ray.kx, t.ray.ky, t.ray.kz,
               value(f, t.ray.shear_x).c_str(), value(f, t.ray.shear_y).c_str());
  for (std::size_t i = 0; i < t.record.size(); i += 4) {
    std::fprintf(stderr, "  record[%2zu..%2zu] = %08" PRIx32 " %08" PRIx32 " %08" PRIx32 " %08" PRIx32 "\n", i, i + 3,
                 t.record[i], t.record[i + 1], t.record[i + 2], t.record[i + 3]);
  }
  std::fprintf(stderr, "  expected (functional) hit %d t %s u %s v %s\n", t.hit ? 1 : 0, value(f, t.result.t).c_str(),
               value(f, t.result.u).c_str(), value(f, t.result.v).c_str());
}

// The netlist testbench's input (sim/rpu_stream_netlist_tb.sv): a header with the count,
// then per test the iu_req words (word 0 first; tag = the test's index) and the iu_rsp
// words the model expects, in hex, so the testbench knows no field.
int write_vectors(const Options& o, TransactionSource& source) {
  std::deque<Transaction> queue;
  std::vector<std::string> lines;
  const std::uint32_t tag_mask = (1u << streams::kRayTagBits) - 1;
  while (static_cast<std::int64_t>(lines.size()) < o.vectors) {
    if (queue.empty() && !source.next(queue)) break;
    while (!queue.empty() && static_cast<std::int64_t>(lines.size()) < o.vectors) {
      const std::uint32_t tag = static_cast<std::uint32_t>(lines.size()) & tag_mask;
      std::string line;
      char word[16];
      for (const std::uint32_t w : iu_request_of(queue.front().test, tag).pack()) {
        std::snprintf(word, sizeof word, "%08" PRIx32 " ", w);
        line += word;
      }
      for (const std::uint32_t w : expected_of(queue.front().test, tag).pack()) {
        std::snprintf(word, sizeof word, " %08" PRIx32, w);
        line += word;
      }
      lines.push_back(line + "\n");
      queue.pop_front();
    }
  }
  OutputFile file(o.write_vectors);
  file.stream() << lines.size() << "\n";
  for (const std::string& l : lines) file.stream() << l;
  file.commit();
  std::printf("iu_cosim: wrote %zu IU tests to %s\n", lines.size(), o.write_vectors.c_str());
  return 0;
}

struct Pending {
  Transaction x;
  std::uint32_t tag;
  std::uint64_t accepted;  // unheld cycles (below) at the request transfer; ~0 once its response showed
};

// Latency (request transfer to the first cycle of rsp_valid) and interval (cycles between
// request transfers), with req_valid and rsp_ready always high, from a burst of tests;
// and the burst's tests per cycle, its first request transfer to its last response.
struct Timing {
  std::uint64_t latency = 0, interval = 0;
  double tests_per_cycle = 0;
};

// The tests of the full-rate burst: enough that the pipeline's fill is a small part.
constexpr std::size_t kBurstTests = 1000;

Timing measure_timing(Model<harness::Iu>& model, const std::vector<Transaction>& burst) {
  Clock clock(model);
  harness::Iu::Inputs in;
  clock.reset(in);
  in.rsp_ready = true;
  Timing timing;
  std::uint64_t first_accept = 0, last_accept = 0, last_response = 0;
  std::size_t next = 0, done = 0;
  std::deque<std::uint64_t> accepted;
  for (; done < burst.size() && clock.cycle() < 100 * kBurstTests; clock.tick()) {
    const std::uint64_t cycle = clock.cycle();
    if (next < burst.size()) in.req = iu_request_of(burst[next].test, static_cast<std::uint32_t>(next));
    in.req_valid = next < burst.size();
    const harness::Iu::Outputs out = clock.settle(in);
    if (out.rsp_valid) {
      timing.latency = std::max(timing.latency, cycle - accepted.front());
      accepted.pop_front();
      last_response = cycle;
      ++done;
    }
    if (in.req_valid && out.req_ready) {
      if (next > 0) timing.interval = std::max(timing.interval, cycle - last_accept);
      if (next == 0) first_accept = cycle;
      last_accept = cycle;
      accepted.push_back(cycle);
      ++next;
    }
  }
  timing.tests_per_cycle = static_cast<double>(done) / static_cast<double>(last_response - first_accept + 1);
  return timing;
}

// `model` outlives the run, so that its waveforms are kept whether the run passed or
// failed.
int run(const Options& o, fp::Format f, TransactionSource& source, std::unique_ptr<Model<harness::Iu>>& model) {
  const ModelInfo* info = find_model<harness::Iu>({{"format", o.format}, {"isect", o.isect}});
  if (!info) {
    std::fprintf(stderr, "iu_cosim: no model for format %s, isect %s; built: %s\n", o.format.c_str(), o.isect.c_str(),
                 built_models<harness::Iu>().c_str());
    return 2;
  }
  model = make_model<harness::Iu>(*info, o.seed, o.trace);

  Stalls stalled(o.seed ^ 0x5bd1e995u, o.stall_percent / 100.0);
  const std::uint32_t tag_mask = (1u << streams::kRayTagBits) - 1;
  Clock clock(*model);
  harness::Iu::Inputs in;
  clock.reset(in);

  std::deque<Transaction> queue;
  PendingByTag<Pending> pending("iu_req", "iu_rsp", streams::kRayTagBits);
  Watchdog watchdog(1000);
  std::vector<Transaction> burst;  // the first tests again, for the timing burst
  std::int64_t sent = 0, checked = 0, hits = 0;
  std::uint64_t cycles = 0;
  std::uint64_t min_latency = ~std::uint64_t{0}, max_latency = 0;
  // The unit is held in a cycle whose answer is not taken: its pipeline stands still, so
  // a test's latency counts the other cycles only.
  std::uint64_t unheld = 0;
  bool have_current = false;
  Transaction current;
  std::uint32_t current_tag = 0;
  const auto start = std::chrono::steady_clock::now();

  try {
    while (true) {
      const std::uint64_t cycle = clock.cycle();
      if (!have_current) {
        while (queue.empty() && source.next(queue)) {
        }
        if (!queue.empty()) {
          current = std::move(queue.front());
          queue.pop_front();
          current_tag = static_cast<std::uint32_t>(sent) & tag_mask;
          have_current = true;
          if (burst.size() < kBurstTests) burst.push_back(current);
        }
      }
      if (!have_current && pending.empty()) break;
      if (have_current) in.req = iu_request_of(current.test, current_tag);
      in.req_valid = have_current && !stalled();
      in.rsp_ready = !stalled();
      const harness::Iu::Outputs out = clock.settle(in);

      if (Pending* p = out.rsp_valid ? pending.find(out.rsp.tag) : nullptr; p && p->accepted != ~std::uint64_t{0}) {
        // Fixed latency: the response is first valid exactly `latency` unheld cycles after
        // the request.
        const std::uint64_t latency = unheld - p->accepted;
        min_latency = std::min(min_latency, latency);
        max_latency = std::max(max_latency, latency);
        p->accepted = ~std::uint64_t{0};
      }
      if (out.rsp_valid && in.rsp_ready) {
        const Pending p = pending.take(out.rsp.tag);
        const std::string mismatch = field_mismatch(expected_of(p.x.test, p.tag), out.rsp);
        if (!mismatch.empty()) {
          print_failure(mismatch, f, cycle, p.x);
          return 1;
        }
        hits += p.x.test.hit ? 1 : 0;
        ++checked;
        watchdog.progress(cycle);
      }
      if (in.req_valid && out.req_ready) {
        pending.add(current_tag, {std::move(current), current_tag, unheld});
        have_current = false;
        ++sent;
      }
      if (!pending.empty()) {
        watchdog.check(cycle, true, [&] { return pending.oldest().x.where; });
      } else {
        watchdog.progress(cycle);
      }
      if (!(out.rsp_valid && !in.rsp_ready)) ++unheld;
      clock.tick();
    }
    harness::Iu::Inputs idle = in;
    idle.req_valid = false;
    idle.rsp_ready = true;
    cycles = clock.cycle();  // the run's, without the quiet cycles below
    expect_quiet(clock, idle, 64, [](const harness::Iu::Outputs& out) {
      return out.rsp_valid ? "an iu_rsp (tag " + hex(out.rsp.tag, streams::kRayTagBits) + ")" : std::string();
    });
  } catch (const CosimFailure& e) {
    std::fprintf(stderr, "iu cosim FAIL: format %s, isect %s: %s\n", o.format.c_str(), o.isect.c_str(), e.what());
    return 1;
  }
  const std::uint64_t cycle = cycles;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (checked == 0) {
    std::fprintf(stderr, "iu cosim FAIL: the rays made no IU test\n");
    return 1;
  }
  if (min_latency != max_latency) {
    std::fprintf(stderr, "iu cosim FAIL: latency varies from %" PRIu64 " to %" PRIu64 " cycles; it must be fixed\n",
                 min_latency, max_latency);
    return 1;
  }

  // Latency and interval at full rate, on a fresh model.
  std::unique_ptr<Model<harness::Iu>> fresh = make_model<harness::Iu>(*info, o.seed, "");
  const Timing timing = measure_timing(*fresh, burst);
  std::printf("iu cosim ok: format %s (%s), isect %s: %" PRId64 " rays, %" PRId64
              " IU tests (%" PRId64 " hits) match the functional model in %" PRIu64
              " cycles, %.2f s (%.0f tests/s, %.0f cycles/s) with %u%% stalls; latency %" PRIu64
              " cycles, interval %" PRIu64 " cycles, %.3f tests per cycle at full rate\n",
              o.format.c_str(), f.name().c_str(), o.isect.c_str(), source.rays_traced(), checked, hits, cycle, seconds,
              static_cast<double>(checked) / seconds, static_cast<double>(cycle) / seconds, o.stall_percent,
              timing.latency, timing.interval, timing.tests_per_cycle);
  if (timing.latency != min_latency) {
    std::fprintf(stderr, "iu cosim FAIL: latency %" PRIu64 " at full rate but %" PRIu64 " with stalls\n",
                 timing.latency, min_latency);
    return 1;
  }

  if (timing.tests_per_cycle < o.min_tests_per_cycle) {
    std::fprintf(stderr, "iu cosim FAIL: %.3f tests per cycle at full rate, under the required %.3f\n",
                 timing.tests_per_cycle, o.min_tests_per_cycle);
    return 1;
  }

  if (o.check_config) {
    // spec/latencies.toml's [iu.<format>].
    const auto m = std::find_if(spec::kIuLatencies.begin(), spec::kIuLatencies.end(),
                                [&](const auto& e) { return e.format == o.format; });
    if (m == spec::kIuLatencies.end()) {
      std::fprintf(stderr, "iu cosim FAIL: spec/latencies.toml has no [iu.%s]; the RTL's %s latency is %" PRIu64
                           ", interval %" PRIu64 "\n", o.format.c_str(), o.isect.c_str(), timing.latency,
                   timing.interval);
      return 1;
    }
    const bool woop = o.isect == "woop";
    const int want_latency = woop ? m->value.woop : m->value.watertight;
    const int want_interval = woop ? m->value.interval_woop : m->value.interval_watertight;
    const bool ok = static_cast<std::uint64_t>(want_latency) == timing.latency &&
                    static_cast<std::uint64_t>(want_interval) == timing.interval;
    std::printf("%s [iu.%s] %s = %d, interval_%s = %d; RTL latency %" PRIu64 ", interval %" PRIu64 "\n",
                ok ? "ok  " : "FAIL", o.format.c_str(), o.isect.c_str(), want_latency, o.isect.c_str(), want_interval,
                timing.latency, timing.interval);
    if (!ok) {
      std::fprintf(stderr, "iu cosim FAIL: spec/latencies.toml disagrees with the RTL's measured IU timing; set "
                           "[iu.%s] to the RTL's numbers above\n", o.format.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace
}  // namespace rpu::sim

int main(int argc, char** argv) {
  using namespace rpu::sim;
  Options o;
  CLI::App app{"Co-simulate the RTL intersection unit against the functional tracer's IU tests"};
  app.add_option("--format", o.format, "format name (spec/formats.toml)")->required();
  app.add_option("--isect", o.isect, "intersection mode")->required()->check(CLI::IsMember({"woop", "watertight"}));
  app.add_option("--scene", o.scenes, "scene (cornell, balls:2, a scene file); repeatable")->required();
  app.add_option("--rays", o.rays, "camera and random rays per scene (and a shadow ray per camera hit)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "random rays, stalls and register-initialisation seed");
  app.add_option("--stall-percent", o.stall_percent, "percent of cycles without req valid / rsp ready")
      ->check(CLI::Range(0, 90));
  app.add_option("--trace", o.trace, "write FST waveforms of the whole run to this file");
  app.add_flag("--check-config", o.check_config,
               "fail unless spec/latencies.toml's [iu.FORMAT] equals the measured latency and interval");
  app.add_option("--min-tests-per-cycle", o.min_tests_per_cycle,
                 "fail when the full-rate burst (the first 1,000 tests) runs fewer tests per cycle")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--write-vectors", o.write_vectors, "write IU tests and results for the netlist testbench");
  app.add_option("--vectors", o.vectors, "with --write-vectors: how many")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  rpu::report_sigbus_as_write_failure("iu_cosim");
  try {
    check_output_paths(o.trace, o.write_vectors);
    const rpu::fp::Format f = rpu::fp::format_by_name(o.format);
    const rpu::IsectMode mode = o.isect == "woop" ? rpu::IsectMode::kWoop : rpu::IsectMode::kWatertight;
    TransactionSource source(o, f, mode);
    if (!o.write_vectors.empty()) return write_vectors(o, source);
    std::unique_ptr<Model<harness::Iu>> model;
    const int status = run(o, f, source, model);
    if (model) model->close_trace();
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "iu_cosim: %s\n", e.what());
    return 2;
  }
}
