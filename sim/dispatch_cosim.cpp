// The ray dispatch alone: a Verilated rpu_ray_dispatch against the cycle model's
// RayDispatch (docs/rtl.md "Ray dispatch"). Each run gives every core a queue of rays in
// packets of 1 to 4 (the last marked packet_end), lets each unit take rays in a random
// two thirds of the cycles while its table of unit_rays has room, and answers each unit's rays after
// a random delay; in every cycle the core the RTL serves and the unit it sends to must be
// the ones the model's send() picks from the same units. The model times pipelined units,
// whose tables never fill (docs/chip.md "Rays in flight per unit"): a unit here takes a
// ray only while its table has room, so room is the unit's choice in both.
//
//   dispatch_cosim --cores 4 --units 4 --packets 1 [--runs N] [--cycles N] [--seed S]
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "cosim_core.hpp"
#include "cycle/dispatch.hpp"
#include "model.hpp"
#include "rpu/harness/dispatch.hpp"

namespace rpu::sim {
namespace {

using harness::Dispatch;

struct Options {
  int cores = 4, units = 4, packets = 1;
  int runs = 500;
  int cycles = 400;
  std::uint64_t seed = 1;
};

// A ray answered by its unit from cycle `at` on.
struct Answer {
  std::uint64_t at;
  std::uint32_t tag;
};

// One run: the first cycle whose choices differ, as a message; nothing when none does.
std::optional<std::string> run_once(const Options& o, const ModelInfo& info, std::uint64_t seed,
                                    std::uint64_t& rays_sent) {
  std::mt19937_64 rng(seed);
  const auto cores = static_cast<std::size_t>(o.cores), units = static_cast<std::size_t>(o.units);
  auto model = make_model<Dispatch>(info, seed, "");
  Clock<Model<Dispatch>> clock(*model);
  Dispatch::Inputs in;
  clock.reset(in);

  cycle::RayDispatch dispatch(cores, o.packets != 0);
  std::vector<std::deque<bool>> ends(cores);  // per core, its rays' packet_end in order
  for (std::size_t c = 0; c < cores; ++c) {
    for (int p = 0; p < 24; ++p) {
      const int n = 1 + static_cast<int>(rng() % 4);
      for (int i = 0; i < n; ++i) {
        ends[c].push_back(i == n - 1);
        cycle::Ray ray;
        ray.core = static_cast<std::uint32_t>(c);
        ray.packet_end = i == n - 1;
        dispatch.queue(std::move(ray), 0);
      }
    }
  }
  // Each unit's rays in flight, by tag, and its answers due.
  const auto table = static_cast<std::uint32_t>(info.number("unit_rays"));
  std::vector<std::uint32_t> in_flight(units, 0);
  std::vector<std::deque<Answer>> answers(units);
  for (std::uint64_t t = 0; t < static_cast<std::uint64_t>(o.cycles); ++t) {
    std::vector<bool> takes(units);
    for (std::size_t u = 0; u < units; ++u) {
      takes[u] = rng() % 3 != 0 && in_flight[u] < table;
      in.unit_req_ready[u] = takes[u];
      in.unit_rsp_valid[u] = !answers[u].empty() && answers[u].front().at <= t;
      in.unit_rsp[u] = {};
      if (in.unit_rsp_valid[u]) in.unit_rsp[u].tag = answers[u].front().tag;
    }
    for (std::size_t c = 0; c < cores; ++c) {
      in.core_req_valid[c] = !ends[c].empty();
      in.core_req[c] = {};
      in.core_req[c].packet_end = !ends[c].empty() && ends[c].front();
      in.core_req[c].tag = static_cast<std::uint32_t>(c) << (streams::kTraceTagBits - streams::kCoreBits);
      in.core_rsp_ready[c] = true;
    }
    const Dispatch::Outputs out = clock.settle(in);
    int rtl_core = -1, rtl_unit = -1;
    for (std::size_t c = 0; c < cores; ++c) {
      if (out.core_req_ready[c]) rtl_core = static_cast<int>(c);
    }
    for (std::size_t u = 0; u < units; ++u) {
      if (out.unit_req_valid[u]) rtl_unit = static_cast<int>(u);
    }
    const std::optional<cycle::RayDispatch::Sent> sent = dispatch.send(t, takes);
    const int model_core = sent ? static_cast<int>(sent->ray.core) : -1;
    const int model_unit = sent ? static_cast<int>(sent->unit) : -1;
    if (rtl_core != model_core || rtl_unit != model_unit) {
      const auto choice = [](int core, int unit) {
        return core < 0 ? std::string("sends no ray") : fmt::format("sends core {}'s ray to unit {}", core, unit);
      };
      return fmt::format("seed {} cycle {}: the RTL {}, the model {}", seed, t, choice(rtl_core, rtl_unit),
                         choice(model_core, model_unit));
    }
    if (rtl_core >= 0) {
      ends[static_cast<std::size_t>(rtl_core)].pop_front();
      const auto u = static_cast<std::size_t>(rtl_unit);
      ++in_flight[u];
      answers[u].push_back({t + 1 + rng() % 40, out.unit_req[u].tag});
      ++rays_sent;
    }
    for (std::size_t u = 0; u < units; ++u) {
      if (in.unit_rsp_valid[u] && out.unit_rsp_ready[u]) {
        answers[u].pop_front();
        --in_flight[u];
      }
    }
    clock.tick();
  }
  return std::nullopt;
}

int run(const Options& o) {
  const std::string cores = std::to_string(o.cores), units = std::to_string(o.units),
                    packets = std::to_string(o.packets);
  const ModelInfo* info = find_model<Dispatch>({{"cores", cores}, {"units", units}, {"packets", packets}});
  if (!info) {
    std::fprintf(stderr, "dispatch_cosim: no model of %d cores, %d units, packets %d; built: %s\n", o.cores, o.units,
                 o.packets, built_models<Dispatch>().c_str());
    return 2;
  }
  std::uint64_t rays = 0;
  for (int r = 0; r < o.runs; ++r) {
    if (const std::optional<std::string> diff = run_once(o, *info, o.seed + static_cast<std::uint64_t>(r), rays)) {
      std::fprintf(stderr, "FAIL %s\n", diff->c_str());
      return 1;
    }
  }
  std::printf("dispatch_cosim %s: %d runs of %d cycles, %llu rays, the same core and unit every cycle\n",
              std::string(info->facts()).c_str(), o.runs, o.cycles, static_cast<unsigned long long>(rays));
  return 0;
}

}  // namespace
}  // namespace rpu::sim

int main(int argc, char** argv) {
  rpu::sim::Options o;
  CLI::App app{"The ray dispatch's RTL against the cycle model's, cycle by cycle, on random rays"};
  app.add_option("--cores", o.cores, "the model's cores")->check(CLI::Range(1, 16));
  app.add_option("--units", o.units, "the model's ray units")->check(CLI::Range(1, 16));
  app.add_option("--packets", o.packets, "1: a chunk's rays go to one unit as a packet")->check(CLI::Range(0, 1));
  app.add_option("--runs", o.runs, "runs, each from its own seed")->check(CLI::Range(1, 1000000));
  app.add_option("--cycles", o.cycles, "cycles a run")->check(CLI::Range(1, 1000000));
  app.add_option("--seed", o.seed, "the first run's seed");
  CLI11_PARSE(app, argc, argv);
  try {
    return rpu::sim::run(o);
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "dispatch_cosim: %s\n", e.what());
    return 2;
  }
}
