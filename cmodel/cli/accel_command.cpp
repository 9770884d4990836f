// rpu accel: the acceleration structures side by side on one scene and one set of rays
// (docs/accel.md): build time, memory, and what each ray cost, checked against brute force.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "accel/beam.hpp"
#include "accel/bounding_volumes.hpp"
#include "accel/bvh.hpp"
#include "accel/minimum_sphere.hpp"
#include "accel/ray_sets.hpp"
#include "accel/structure.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/output_file.hpp"
#include "image/image.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

struct AccelOptions {
  std::string scene;
  std::string rays = "primary";
  int count = 100000;
  int width = 256, height = 256;
  std::uint32_t seed = 1;
  std::filesystem::path csv;
  double grid_lambda = accel::StructureOptions{}.grid_lambda;
  bool bounds = false;
  int beam = 0;  // pixels a side of a beam of primary rays through the BVH; 0: no beams
  std::string heatmap;  // prefix of the per-structure heatmaps; empty: none
  std::vector<std::string> structures = accel::structure_names();  // the rows, in table order
};

// The structures to build, in structure_names()'s order.
std::vector<std::string> chosen_structures(const AccelOptions& o) {
  std::vector<std::string> chosen;
  for (const std::string& name : accel::structure_names()) {
    if (std::find(o.structures.begin(), o.structures.end(), name) != o.structures.end()) chosen.push_back(name);
  }
  return chosen;
}

// --heatmap PREFIX: the file of one structure's heatmap.
std::filesystem::path heatmap_path(const std::string& prefix, const std::string& structure) {
  return prefix + "-" + structure + ".png";
}

// Brute force traces only as many rays as keep its triangle tests under this budget
// (about ten seconds); the other structures are checked against it on those rays.
constexpr double kBruteForceTestBudget = 1e9;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// One structure's row: its build, and both queries over the rays it traced.
struct Row {
  std::string name, parameters;
  double build_seconds = 0.0;
  std::uint64_t memory_bytes = 0, nodes = 0;
  std::size_t rays = 0;  // traced: all, or brute force's share
  accel::RayCost closest_cost, any_cost;
  double closest_seconds = 0.0, any_seconds = 0.0;
  std::size_t checked = 0, mismatches = 0;
  double frustum_nodes_per_ray = 0.0, frustum_triangles_per_ray = 0.0;  // beams only
  std::vector<std::uint64_t> pixel_cost;  // --heatmap: each primary ray's nodes + tests
};

// The heatmaps of the rows that have per-pixel costs, all on one scale: false colour over
// 0..the largest cost of any of them, so that the pictures compare.
void write_heatmaps(const AccelOptions& o, const std::vector<Row>& rows) {
  std::uint64_t largest = 1;
  for (const Row& r : rows) {
    for (const std::uint64_t c : r.pixel_cost) largest = std::max(largest, c);
  }
  for (const Row& r : rows) {
    if (r.pixel_cost.empty()) continue;
    Image image(o.width, o.height);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      image.pixels[i] = false_colour(double(r.pixel_cost[i]) / double(largest));
    }
    write_image(image, heatmap_path(o.heatmap, r.name));
  }
  fmt::print("heatmaps {}: nodes + triangle tests per primary ray, false colour over 0..{}\n",
             heatmap_path(o.heatmap, "STRUCTURE").string(), largest);
}

std::string human_bytes(double bytes) {
  if (bytes < 1e4) return fmt::format("{:.0f} B", bytes);
  if (bytes < 1e7) return fmt::format("{:.1f} kB", bytes * 1e-3);
  if (bytes < 1e10) return fmt::format("{:.1f} MB", bytes * 1e-6);
  return fmt::format("{:.1f} GB", bytes * 1e-9);
}

std::string mrays_per_second(std::size_t rays, double seconds) {
  return rays > 0 && seconds > 0.0 ? fmt::format("{:.3f}", double(rays) * 1e-6 / seconds) : "-";
}

double per_ray(std::uint64_t total, std::size_t rays) { return rays > 0 ? double(total) / double(rays) : 0.0; }

std::string describe(const Ray& r) {
  return fmt::format("origin ({:.17g}, {:.17g}, {:.17g}) direction ({:.17g}, {:.17g}, {:.17g}) t in ({:.17g}, {:.17g})",
                     r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y, r.direction.z, r.t_min,
                     r.t_max);
}

std::string describe(const Hit& h) {
  return h.hit() ? fmt::format("triangle {} at t = {:.17g}", h.prim, h.t) : std::string("no hit");
}

std::vector<Ray> make_rays(const AccelOptions& o, const Scene& scene, const accel::TriangleSet& triangles) {
  if (o.rays == "random") return accel::random_rays(triangles, o.count, o.seed);
  std::vector<Ray> primary = accel::primary_rays(scene, o.width, o.height);
  if (o.rays == "primary") return primary;
  if (scene.lights.empty()) {
    throw Error(fmt::format("{} has no lights, so there are no shadow rays; add a light to the scene or choose "
                            "--rays primary or random",
                            scene.source));
  }
  const accel::Bvh bvh(triangles);
  std::vector<Hit> hits;
  hits.reserve(primary.size());
  accel::RayCost unused;
  for (const Ray& r : primary) hits.push_back(bvh.closest_hit(r, unused));
  return accel::shadow_rays(scene, triangles, primary, hits, o.seed);
}

void write_csv(const std::filesystem::path& path, const AccelOptions& o, const Scene& scene,
               const accel::TriangleSet& triangles, const std::vector<Row>& rows) {
  OutputFile file(path);
  std::ostream& out = file.stream();
  out << "scene,triangles,rays,structure,parameters,build_seconds,memory_bytes,nodes,traced_rays,"
         "closest_nodes_per_ray,closest_tests_per_ray,closest_bytes_per_ray,closest_rays_per_second,"
         "any_nodes_per_ray,any_tests_per_ray,any_bytes_per_ray,any_rays_per_second,checked_rays,mismatches,"
         "frustum_nodes_per_ray,frustum_triangles_per_ray\n";
  for (const Row& r : rows) {
    auto rate = [&](double seconds) { return r.rays > 0 && seconds > 0.0 ? double(r.rays) / seconds : 0.0; };
    out << fmt::format("{},{},{},{},{},{:.6g},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{},{:.6g},"
                       "{:.6g}\n",
                       csv_field(scene.source), triangles.size(), o.rays, r.name, csv_field(r.parameters),
                       r.build_seconds, r.memory_bytes, r.nodes, r.rays, per_ray(r.closest_cost.nodes, r.rays),
                       per_ray(r.closest_cost.tests, r.rays), per_ray(r.closest_cost.bytes, r.rays),
                       rate(r.closest_seconds), per_ray(r.any_cost.nodes, r.rays), per_ray(r.any_cost.tests, r.rays),
                       per_ray(r.any_cost.bytes, r.rays), rate(r.any_seconds), r.checked, r.mismatches,
                       r.frustum_nodes_per_ray, r.frustum_triangles_per_ray);
  }
  file.commit();
}

// --bounds: each object's bounding volumes against its minimum sphere, per object and
// summed over the scene's objects; Ritter's radius against the minimum one.
int run_bounds(const AccelOptions& o, const Scene& scene) {
  const std::vector<std::vector<glm::dvec3>> objects = accel::scene_objects(scene);
  struct Kind {
    const char* name;
    const char* key;
    double summed = 0.0, ratio_sum = 0.0;  // volume; the objects' volume / minimum sphere's
  };
  std::array<Kind, 4> kinds{{{"axis-aligned box", "aabb"}, {"PCA box", "obb"}, {"Ritter sphere", "ritter"},
                             {"minimum sphere (CGAL)", "minimum"}}};
  double radius_ratio_sum = 0.0, radius_ratio_max = 0.0;
  std::size_t points = 0, measured = 0;
  for (const std::vector<glm::dvec3>& object : objects) {
    points += object.size();
    Bounds b;
    for (const glm::dvec3& p : object) b.extend(p);
    const accel::Sphere ritter = accel::ritter_sphere(object), smallest = accel::minimum_sphere(object);
    const std::array<double, 4> volumes{accel::volume(b), accel::volume(accel::pca_box(object)),
                                        accel::volume(ritter), accel::volume(smallest)};
    for (std::size_t k = 0; k < kinds.size(); ++k) kinds[k].summed += volumes[k];
    if (!(smallest.radius > 0.0)) continue;
    for (std::size_t k = 0; k < kinds.size(); ++k) kinds[k].ratio_sum += volumes[k] / volumes[3];
    radius_ratio_sum += ritter.radius / smallest.radius;
    radius_ratio_max = std::max(radius_ratio_max, ritter.radius / smallest.radius);
    ++measured;
  }
  auto mean = [&](double sum) { return measured > 0 ? sum / double(measured) : 0.0; };
  fmt::print("{}: {} objects (classes of triangles sharing a vertex), {} distinct vertices\n", scene.source,
             objects.size(), points);
  fmt::print("{:<22} {:>14} {:>22}\n", "bounding volume", "volume, summed", "mean of / minimum's");
  for (const Kind& k : kinds) fmt::print("{:<22} {:>14.6g} {:>22.4f}\n", k.name, k.summed, mean(k.ratio_sum));
  fmt::print("Ritter's radius / the minimum: mean {:.4f}, largest {:.4f} over {} objects\n", mean(radius_ratio_sum),
             radius_ratio_max, measured);
  if (!o.csv.empty()) {
    OutputFile file(o.csv);
    std::ostream& out = file.stream();
    out << "scene,objects,points";
    for (const Kind& k : kinds) out << fmt::format(",{0}_volume,{0}_volume_ratio_mean", k.key);
    out << ",ritter_radius_ratio_mean,ritter_radius_ratio_max\n";
    out << fmt::format("{},{},{}", csv_field(scene.source), objects.size(), points);
    for (const Kind& k : kinds) out << fmt::format(",{:.9g},{:.9g}", k.summed, mean(k.ratio_sum));
    out << fmt::format(",{:.9g},{:.9g}\n", mean(radius_ratio_sum), radius_ratio_max);
    file.commit();
  }
  return 0;
}

// --beam: the primary rays in beams of o.beam x o.beam pixels through the BVH
// (accel/beam.hpp), closest hits only, checked against brute force like every row.
template <typename Check>
Row beam_row(const AccelOptions& o, const std::vector<Ray>& rays, const accel::TriangleSet& triangles,
             const Check& check) {
  Row row;
  row.name = "bvh-beam";
  const Clock::time_point build_start = Clock::now();
  const accel::Bvh bvh(triangles);
  row.build_seconds = seconds_since(build_start);
  row.memory_bytes = bvh.memory_bytes();
  row.nodes = bvh.node_count();
  row.rays = rays.size();
  accel::BeamCost cost;
  const Clock::time_point start = Clock::now();
  const std::vector<Hit> hits = accel::trace_primary_beams(bvh, rays, o.width, o.height, o.beam, cost);
  row.closest_seconds = seconds_since(start);
  // The rays' own box and triangle tests; the frustum's tests apart, in the parameters.
  row.closest_cost = {cost.ray_nodes, cost.ray_tests, cost.bytes};
  row.frustum_nodes_per_ray = per_ray(cost.frustum_nodes, rays.size());
  row.frustum_triangles_per_ray = per_ray(cost.frustum_triangles, rays.size());
  row.parameters = fmt::format("{0}x{0} pixel beams through the bvh; per ray {1:.2f} frustum node and {2:.2f} "
                               "frustum triangle tests",
                               o.beam, row.frustum_nodes_per_ray, row.frustum_triangles_per_ray);
  check(row, hits, nullptr);
  return row;
}

int run_accel(const AccelOptions& o) {
  // Options that do not go together, refused before any work.
  if (o.bounds && (o.beam > 0 || !o.heatmap.empty())) {
    throw Error("--bounds measures bounding volumes instead of tracing rays; leave out --beam and --heatmap");
  }
  if (!o.heatmap.empty() && o.rays != "primary") {
    throw Error(fmt::format("--heatmap draws primary rays' costs as an image; leave it out with --rays {}", o.rays));
  }
  if (o.beam > 0 && o.rays != "primary") {
    throw Error(fmt::format("--beam {} traces beams of primary rays; leave it out with --rays {}", o.beam, o.rays));
  }
  std::vector<PlannedInput> inputs;
  if (std::error_code ec; std::filesystem::is_regular_file(o.scene, ec)) inputs.push_back({"the scene", o.scene});
  std::vector<PlannedOutput> outputs;
  if (!o.csv.empty()) outputs.push_back({"--csv", o.csv, {".csv"}});
  if (!o.heatmap.empty()) {
    for (const std::string& name : chosen_structures(o)) {
      if (name != "brute") outputs.push_back({"--heatmap", heatmap_path(o.heatmap, name), {".png"}});
    }
  }
  check_outputs(outputs, inputs);

  const Scene scene = resolve_scene(o.scene);
  for (const std::string& w : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
  if (o.bounds) return run_bounds(o, scene);
  const accel::TriangleSet triangles(scene);
  if (triangles.skipped() > 0) {
    fmt::print(stderr, "rpu: warning: {}: {} triangles skipped by every structure (a vertex index out of range, "
               "a vertex not finite, or degenerate)\n", scene.source, triangles.skipped());
  }
  const std::vector<Ray> rays = make_rays(o, scene, triangles);
  const double brute_rays = kBruteForceTestBudget / double(std::max<std::size_t>(1, triangles.size()));
  const std::size_t checked = std::min(rays.size(), static_cast<std::size_t>(std::max(1.0, brute_rays)));

  accel::StructureOptions options;
  options.grid_lambda = o.grid_lambda;
  std::vector<Row> rows;
  std::vector<Hit> expected_hits;
  std::vector<char> expected_any;
  std::string first_mismatch;
  // A row's answers against brute force's on the rays both traced (any hits when given).
  const auto check = [&](Row& row, const std::vector<Hit>& hits, const std::vector<char>* any) {
    row.checked = std::min(row.rays, expected_hits.size());
    for (std::size_t i = 0; i < row.checked; ++i) {
      const bool closest_differs = hits[i].prim != expected_hits[i].prim || hits[i].t != expected_hits[i].t;
      const bool any_differs = any != nullptr && (*any)[i] != expected_any[i];
      if (!closest_differs && !any_differs) continue;
      ++row.mismatches;
      if (!first_mismatch.empty()) continue;
      first_mismatch = closest_differs
                           ? fmt::format("{} closest hit of ray {} ({}): {}, brute force: {}", row.name, i,
                                         describe(rays[i]), describe(hits[i]), describe(expected_hits[i]))
                           : fmt::format("{} any hit of ray {} ({}): {}, brute force: {}", row.name, i,
                                         describe(rays[i]), (*any)[i] ? "hit" : "no hit",
                                         expected_any[i] ? "hit" : "no hit");
    }
  };
  const std::vector<std::string> structures = chosen_structures(o);
  const bool with_brute = structures.front() == "brute";
  for (const std::string& name : structures) {
    Row row;
    row.name = name;
    const Clock::time_point build_start = Clock::now();
    const std::unique_ptr<accel::Structure> s = accel::build_structure(name, triangles, options);
    row.build_seconds = seconds_since(build_start);
    row.parameters = s->parameters();
    row.memory_bytes = s->memory_bytes();
    row.nodes = s->node_count();
    const bool brute = name == "brute";
    row.rays = brute ? checked : rays.size();

    std::vector<Hit> hits(row.rays);
    Clock::time_point start = Clock::now();
    for (std::size_t i = 0; i < row.rays; ++i) hits[i] = s->closest_hit(rays[i], row.closest_cost);
    row.closest_seconds = seconds_since(start);
    std::vector<char> any(row.rays);
    start = Clock::now();
    for (std::size_t i = 0; i < row.rays; ++i) any[i] = s->any_hit(rays[i], row.any_cost);
    row.any_seconds = seconds_since(start);

    if (!o.heatmap.empty() && !brute) {
      // Apart from the timed pass, one ray at a time.
      row.pixel_cost.resize(row.rays);
      for (std::size_t i = 0; i < row.rays; ++i) {
        accel::RayCost cost;
        s->closest_hit(rays[i], cost);
        row.pixel_cost[i] = cost.nodes + cost.tests;
      }
    }
    if (brute) {
      expected_hits.assign(hits.begin(), hits.end());
      expected_any = any;
    } else {
      row.checked = std::min(row.rays, expected_hits.size());
      check(row, hits, &any);
    }
    rows.push_back(std::move(row));
  }
  if (o.beam > 0) rows.push_back(beam_row(o, rays, triangles, check));

  const bool shadow = o.rays == "shadow";
  fmt::print("{}: {} triangles, {} {} rays{}; per ray: {} hit\n", scene.source, triangles.size(), rays.size(), o.rays,
             with_brute && checked < rays.size() ? fmt::format(" (brute force: the first {})", checked) : std::string(),
             shadow ? "any" : "closest");
  fmt::print("{:<8} {:>10} {:>10} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10}  {}\n", "struct", "build ms", "memory",
             "nodes", "nodes/ray", "tests/ray", "bytes/ray", "closest", "any", "parameters");
  fmt::print("{:<8} {:>10} {:>10} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "", "", "", "", "", "", "", "Mrays/s",
             "Mrays/s");
  for (const Row& r : rows) {
    const accel::RayCost& cost = shadow ? r.any_cost : r.closest_cost;
    fmt::print("{:<8} {:>10.3f} {:>10} {:>9} {:>10.2f} {:>10.2f} {:>10.1f} {:>10} {:>10}  {}\n", r.name,
               r.build_seconds * 1e3, human_bytes(double(r.memory_bytes)), r.nodes, per_ray(cost.nodes, r.rays),
               per_ray(cost.tests, r.rays), per_ray(cost.bytes, r.rays), mrays_per_second(r.rays, r.closest_seconds),
               mrays_per_second(r.rays, r.any_seconds), r.parameters);
  }
  if (!o.csv.empty()) write_csv(o.csv, o, scene, triangles, rows);
  if (!o.heatmap.empty()) write_heatmaps(o, rows);

  std::size_t mismatches = 0;
  for (const Row& r : rows) mismatches += r.mismatches;
  if (mismatches > 0) {
    throw Error(fmt::format("{} of the answers differ from brute force on {} rays; the first: {}", mismatches,
                            checked, first_mismatch));
  }
  if (with_brute) {
    fmt::print("every structure's closest and any hits equal brute force's on {} rays\n", checked);
  } else {
    fmt::print("not checked: brute force is not among --structures\n");
  }
  return 0;
}

}  // namespace

Command add_accel_command(CLI::App& app) {
  auto o = std::make_shared<AccelOptions>();
  CLI::App* cmd = app.add_subcommand(
      "accel", "Acceleration structures side by side: build time, memory, nodes, tests and bytes per ray, rays/s");
  cmd->add_option("scene", o->scene, "Scene file, built-in name or mesh file (default: the Cornell box)");
  cmd->add_option("--rays", o->rays,
                  "Rays: primary (one per pixel from the camera), random (between random points of the scene's "
                  "box) or shadow (from the primary hits to the lights)")
      ->check(CLI::IsMember({"primary", "random", "shadow"}))
      ->capture_default_str();
  cmd->add_option("--count", o->count, "Number of random rays")->check(CLI::Range(1, 100000000))->capture_default_str();
  cmd->add_option("--width", o->width, "Image width of primary and shadow rays")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--height", o->height, "Image height of primary and shadow rays")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the random rays and of the points on area lights")->capture_default_str();
  cmd->add_option("--csv", o->csv, "Write the table as CSV (.csv)");
  cmd->add_option("--grid-lambda", o->grid_lambda, "Uniform grid cells per triangle")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_flag("--bounds", o->bounds,
                "Instead of the structures: each object's axis-aligned box, PCA box, Ritter sphere and minimum "
                "sphere, their volumes summed, and Ritter's radius against the minimum");
  cmd->add_option("--structures", o->structures, "The structures to build and trace, comma-separated")
      ->delimiter(',')
      ->check(CLI::IsMember(accel::structure_names()))
      ->capture_default_str();
  cmd->add_option("--beam", o->beam,
                  "Also trace the primary rays in beams of NxN pixels through the BVH (frustum culling; 1..8)")
      ->check(CLI::Range(1, 8));
  cmd->add_option("--heatmap", o->heatmap,
                  "Write PREFIX-STRUCTURE.png for each structure: nodes + triangle tests of each primary ray, in "
                  "false colour on one scale");
  return {cmd, [o] { return run_accel(*o); }};
}

}  // namespace rpu::cli
