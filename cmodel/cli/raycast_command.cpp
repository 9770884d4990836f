// rpu raycast: primary rays straight through the golden trace units, shown as eye-light
// shading or as a false-colour map of the work each ray cost. No shaders run.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "cli/progress.hpp"
#include "common/host_threads.hpp"
#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "image/image.hpp"
#include "render/sampling.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

struct RaycastOptions {
  std::string scene;
  std::filesystem::path output = "raycast.png";
  std::string heatmap;  // "", "nodes" or "tests"
  int width = 512, height = 512, threads = 0;
  ChipOptions chip;
};

int run_raycast(const RaycastOptions& o) {
  std::vector<PlannedInput> inputs;
  if (std::error_code ec; std::filesystem::is_regular_file(o.scene, ec)) inputs.push_back({"the scene", o.scene});
  check_outputs({{"-o", o.output, {".png", ".exr"}}}, inputs);
  const Scene scene = resolve_scene(o.scene);
  for (const std::string& w : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
  const KdBuildConfig build = o.chip.build_config();
  const fp::Format format = o.chip.number_format();
  const functional::SceneImage si = functional::make_scene_image(scene, build, o.chip.isect_mode());
  const functional::Tracer tracer(si.image.bytes, si.layout, format, build.stack_depth);

  const CameraModel camera(scene.camera, o.width, o.height);
  std::vector<functional::TraceHit> hits(static_cast<std::size_t>(o.width) * o.height);
  std::atomic<int> next_row{0}, done_rows{0};
  const auto start = std::chrono::steady_clock::now();
  {
    ProgressBar bar(fmt::format("raycasting {}", scene.source));
    auto worker = [&] {
      std::vector<functional::TraceRay> rays(static_cast<std::size_t>(o.width));
      for (int y; (y = next_row.fetch_add(1)) < o.height;) {
        for (int x = 0; x < o.width; ++x) {
          const PrimaryRay r = camera.ray(x + 0.5, y + 0.5, {0.5, 0.5});
          functional::TraceRay& t = rays[static_cast<std::size_t>(x)];
          for (int i = 0; i < 3; ++i) {
            t.origin[i] = static_cast<float>(r.origin[i]);
            t.direction[i] = static_cast<float>(r.direction[i]);
          }
        }
        tracer.trace(rays, functional::TraceMode::kClosest,
                     std::span(hits).subspan(static_cast<std::size_t>(y) * o.width, static_cast<std::size_t>(o.width)));
        bar.update(static_cast<std::size_t>(done_rows.fetch_add(1) + 1), static_cast<std::size_t>(o.height));
      }
    };
    const unsigned n = o.threads > 0 ? static_cast<unsigned>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    run_host_threads(static_cast<int>(n), [&](int) { worker(); });
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::uint64_t nodes = 0, tests = 0, hit_count = 0;
  std::uint32_t max_nodes = 0, max_tests = 0;
  for (const functional::TraceHit& h : hits) {
    nodes += h.counters.nodes;
    tests += h.counters.tests;
    hit_count += h.hit;
    max_nodes = std::max(max_nodes, h.counters.nodes);
    max_tests = std::max(max_tests, h.counters.tests);
  }
  Image image(o.width, o.height);
  for (int y = 0; y < o.height; ++y) {
    for (int x = 0; x < o.width; ++x) {
      const functional::TraceHit& h = hits[static_cast<std::size_t>(y) * o.width + x];
      if (o.heatmap == "nodes") {
        image.at(x, y) = false_colour(static_cast<double>(h.counters.nodes) / std::max(1u, max_nodes));
      } else if (o.heatmap == "tests") {
        image.at(x, y) = false_colour(static_cast<double>(h.counters.tests) / std::max(1u, max_tests));
      } else if (h.hit) {
        // Eye light: the light sits at the camera, so brightness is |cos| to the view.
        const glm::uvec3 t = scene.triangles[h.prim];
        const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(scene.positions[t.y] - scene.positions[t.x]),
                                                       glm::dvec3(scene.positions[t.z] - scene.positions[t.x])));
        const PrimaryRay r = camera.ray(x + 0.5, y + 0.5, {0.5, 0.5});
        const glm::dvec3 kd = scene.materials[scene.material_ids[h.prim]].diffuse;
        image.at(x, y) = glm::vec3(std::abs(glm::dot(n, r.direction)) * (0.2 + 0.8 * kd));
      } else {
        image.at(x, y) = glm::vec3(scene.background);
      }
    }
  }
  write_image(image, o.output);
  const double rays = static_cast<double>(hits.size());
  fmt::print(stderr,
             "rpu: raycast {} {}x{}, {} {}, {} triangles, {} kd nodes: {} rays, {:.1f}% hit, {:.1f} nodes and {:.1f} "
             "triangle tests per ray (max {} and {}), in {:.2f} s, {:.2f} M rays/s -> {}\n",
             scene.source, o.width, o.height, format.name(), o.chip.isect, scene.triangles.size(),
             si.layout.kd_nodes.count, hits.size(), 100.0 * static_cast<double>(hit_count) / rays,
             static_cast<double>(nodes) / rays, static_cast<double>(tests) / rays, max_nodes, max_tests, seconds,
             rays * 1e-6 / seconds, o.output.string());
  return 0;
}

}  // namespace

Command add_raycast_command(CLI::App& app) {
  auto o = std::make_shared<RaycastOptions>();
  CLI::App* cmd = app.add_subcommand(
      "raycast", "Primary rays through the golden traversal and intersection units: eye-light shading or a cost heatmap");
  cmd->add_option("scene", o->scene, "Scene file, built-in name or mesh file (default: the Cornell box)");
  cmd->add_option("-o,--output", o->output, "Output image: .png or .exr")->capture_default_str();
  cmd->add_option("--heatmap", o->heatmap, "False-colour map of kd nodes visited or triangle tests per ray")
      ->check(CLI::IsMember({"nodes", "tests"}));
  cmd->add_option("--width", o->width, "Image width")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", o->height, "Image height")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--threads", o->threads, "Host threads (0 = all cores)")->check(CLI::Range(0, 1024));
  add_chip_options(*cmd, o->chip);
  return {cmd, [o] { return run_raycast(*o); }};
}

}  // namespace rpu::cli
