// rpu sweep: a sweep file expanded into points, each one `rpu render` run measured
// against its reference, run here with a job limit or handed to GNU parallel or Slurm;
// rpu sweep-point: one point, the line every job list holds (docs/sweeps.md).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/process.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/output_file.hpp"
#include "config/config.hpp"
#include "device/registry.hpp"
#include "fp/format.hpp"
#include "image/image.hpp"
#include "scene/geometry.hpp"
#include "scene/resolve.hpp"
#include "sweep/area.hpp"
#include "sweep/ray_checks.hpp"
#include "sweep/sweep_spec.hpp"

namespace rpu::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The columns of a point's CSV row and of sweep.csv, in order (docs/sweeps.md).
constexpr const char* kColumns[] = {
    "id",           "scene",           "triangles",      "transform",    "fidelity",       "config",
    "set",          "format",          "isect",          "firmware",     "select",         "width",
    "height",       "spp",             "psnr_db",        "max_error",    "dark_dots",      "self_hits",
    "tree_nodes",
    "nodes_per_ray", "tests_per_ray",  "primary_rays",   "hit_mismatches",
    "closed_meshes", "leak_rays",      "leaks",          "axis_rays",    "axis_mismatches", "grazing_rays",
    "grazing_mismatches", "surface_rays", "surface_mismatches", "cycles", "fps",           "rays",
    "rays_per_second", "host_seconds", "datapath_cells", "chip_cells",   "error"};

json point_json(const sweep::Point& p) {
  return {{"id", p.id},         {"scene", p.scene},   {"transform", p.transform}, {"fidelity", p.fidelity},
          {"config", p.config}, {"set", p.sets},      {"format", p.format},       {"isect", p.isect},
          {"firmware", p.firmware}, {"select", p.select}, {"width", p.width},     {"height", p.height},
          {"spp", p.spp},       {"max_depth", p.max_depth}, {"seed", p.seed},     {"reference", p.reference}};
}

sweep::Point point_from_json(const json& j) {
  sweep::Point p;
  p.id = j.at("id");
  p.scene = j.at("scene");
  p.transform = j.at("transform");
  p.fidelity = j.at("fidelity");
  p.config = j.at("config");
  p.sets = j.at("set").get<std::vector<std::string>>();
  p.format = j.at("format");
  p.isect = j.at("isect");
  p.firmware = j.at("firmware").get<std::vector<std::string>>();
  p.select = j.value("select", std::string("1"));
  p.width = j.at("width");
  p.height = j.at("height");
  p.spp = j.at("spp");
  p.max_depth = j.at("max_depth");
  p.seed = j.at("seed");
  p.reference = j.at("reference");
  return p;
}

void write_text(const fs::path& file, const std::string& text) {
  OutputFile out(file);
  out.stream() << text;
  out.commit();
}

json read_json(const fs::path& file) {
  const std::string text = read_input_file(file);
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw Error(fmt::format("{}: not JSON: {}", file.string(), e.what()));
  }
}

// An flock(2) on a file, held until destruction: the kernel releases it when the
// process ends however it ends, so a killed run never leaves a directory locked. The
// holder writes its pid into the file, for the message of the one that waits or is
// refused.
class FileLock {
 public:
  enum class Wait { kNo, kYes };
  // Takes the lock, waiting for it or not; false when another process holds it.
  FileLock(const fs::path& file, Wait wait) {
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0) throw Error(fmt::format("{}: cannot create the lock file: {}", file.string(), std::strerror(errno)));
    int r;
    while ((r = ::flock(fd_, LOCK_EX | (wait == Wait::kNo ? LOCK_NB : 0))) != 0 && errno == EINTR) {
    }
    if (r != 0) {
      if (errno != EWOULDBLOCK) {
        throw Error(fmt::format("{}: cannot lock: {}", file.string(), std::strerror(errno)));
      }
      holder_ = read_input_file(file);
      ::close(fd_);
      fd_ = -1;
      return;
    }
    // The lock holds without the pid if these fail; only messages would miss it.
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd_, 0) == 0) {
      const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
      static_cast<void>(written);
    }
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

  bool held() const { return fd_ >= 0; }
  // Another holder's pid, as it wrote it ("" if it had not yet).
  const std::string& holder() const { return holder_; }

 private:
  int fd_ = -1;
  std::string holder_;
};

// The sweep directory's files.
struct Layout {
  fs::path dir;
  fs::path plan() const { return dir / "plan.json"; }
  fs::path record(const std::string& id) const { return dir / "points" / (id + ".json"); }
  fs::path row(const std::string& id) const { return dir / "points" / (id + ".csv"); }
  fs::path image(const std::string& id, std::string_view ext) const {
    return dir / "images" / fmt::format("{}{}", id, ext);
  }
  fs::path log(const std::string& id) const { return dir / "logs" / (id + ".log"); }
  // Held by rpu sweep while it plans and runs; by rpu sweep-point while it runs a point.
  fs::path sweep_lock() const { return dir / ".rpu-sweep.lock"; }
  fs::path point_lock(const std::string& id) const { return dir / "logs" / (id + ".lock"); }
};

// A point is done when its record exists and is its own: records are written whole
// (OutputFile), so a killed run leaves either none or a complete one.
bool done(const Layout& layout, const std::string& id) {
  std::error_code ec;
  if (!fs::is_regular_file(layout.record(id), ec)) return false;
  try {
    return read_json(layout.record(id)).value("id", "") == id;
  } catch (const Error&) {
    return false;
  }
}

std::string tail(const fs::path& file, std::size_t lines) {
  std::ifstream in(file);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);) all.push_back(line);
  const std::size_t from = all.size() > lines ? all.size() - lines : 0;
  std::string out;
  for (std::size_t i = from; i < all.size(); ++i) out += "  " + all[i] + "\n";
  return out;
}

// The end of a failed point's log; when it is empty, why: a full file system leaves no
// room for the message the point wrote there.
std::string failure_text(const fs::path& log) {
  const std::string text = tail(log, 12);
  if (!text.empty()) return text;
  struct statvfs fs_info {};
  if (::statvfs(log.parent_path().c_str(), &fs_info) == 0 && fs_info.f_bavail == 0) {
    return fmt::format("  (the log is empty: the file system of {} has no space left ({}), so the point's own "
                       "message could not be written; free space and run the sweep again)\n",
                       log.parent_path().string(), std::strerror(ENOSPC));
  }
  return "  (the log is empty)\n";
}

// The PNG beside each EXR, and where the point differs from its reference: the largest
// linear difference of a pixel's channels in false colour, full scale at 1/8.
void write_pictures(const Layout& layout, const sweep::Point& p) {
  const Image image = read_image(layout.image(p.id, ".exr"));
  write_image(image, layout.image(p.id, ".png"));
  if (p.reference.empty()) return;
  const Image reference = read_image(layout.image(p.reference, ".exr"));
  Image diff(image.width, image.height);
  for (std::size_t i = 0; i < diff.pixels.size(); ++i) {
    const glm::vec3 d = glm::abs(image.pixels[i] - reference.pixels[i]);
    const double e = std::max({d.r, d.g, d.b});
    diff.pixels[i] = std::isfinite(e) ? false_colour(std::min(1.0, e * 8.0)) : glm::vec3(1.0f, 0.0f, 1.0f);
  }
  write_image(diff, layout.image(p.id, ".diff.png"));
}

json value_at(const json& tree, std::string_view dotted) {
  const json* node = &tree;
  for (std::size_t start = 0; start <= dotted.size();) {
    const std::size_t dot = std::min(dotted.find('.', start), dotted.size());
    const std::string key(dotted.substr(start, dot - start));
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
    start = dot + 1;
  }
  return *node;
}

// A count of the render's statistics per ray it traced; null where either is missing or
// no ray was traced.
json per_ray(const json& render, std::string_view dotted) {
  const json count = value_at(render, dotted), rays = value_at(render, "rays.total");
  if (!count.is_number() || !rays.is_number() || rays.get<double>() <= 0.0) return nullptr;
  return count.get<double>() / rays.get<double>();
}

std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return csv_field(v.get<std::string>());
  if (v.is_number_float()) return fmt::format("{}", v.get<double>());
  return v.dump();
}

std::string csv_header() { return fmt::format("{}\n", fmt::join(kColumns, ",")); }

std::string csv_line(const json& row) {
  std::vector<std::string> cells;
  for (const char* c : kColumns) cells.push_back(csv_cell(row.value(c, json(nullptr))));
  return fmt::format("{}\n", fmt::join(cells, ","));
}

// --- rpu sweep-point -------------------------------------------------------------------

struct PointOptions {
  fs::path dir;
  std::string id;
};

int run_sweep_point(const PointOptions& o) {
  const Layout layout{fs::absolute(o.dir)};
  // The plan rpu sweep wrote: the point and the sweep's checks.
  std::optional<sweep::Point> found;
  std::string sweep_name;
  bool plan_hit_check = false;
  std::uint32_t plan_leak_rays = 0, plan_extreme_rays = 0;
  try {
    const json plan = read_json(layout.plan());
    for (const char* list : {"references", "points"}) {
      for (const json& j : plan.at(list)) {
        if (j.at("id") == o.id) found = point_from_json(j);
      }
    }
    sweep_name = plan.at("sweep");
    plan_hit_check = plan.at("hit_check");
    plan_leak_rays = plan.at("leak_rays");
    plan_extreme_rays = plan.at("extreme_rays");
  } catch (const json::exception& e) {
    throw Error(fmt::format("{}: not a plan that rpu sweep wrote ({}); run rpu sweep SPEC -o {} again",
                            layout.plan().string(), e.what(), o.dir.string()));
  }
  if (!found) throw Error(fmt::format("{}: no point '{}' in the sweep", layout.plan().string(), o.id));
  const sweep::Point& p = *found;
  // Two runs of one point (a job list run twice, rpu sweep beside run-parallel.sh)
  // take turns: the second waits, then finds the point done.
  const FileLock lock(layout.point_lock(p.id), FileLock::Wait::kYes);
  if (done(layout, p.id)) {
    fmt::print("{}: done already\n", p.id);
    return 0;
  }
  if (!p.reference.empty() && !done(layout, p.reference)) {
    throw Error(fmt::format("{}: its reference {} is not rendered yet; run the references first "
                            "(jobs/references.txt)",
                            p.id, p.reference));
  }
  const fs::path render_stats = layout.dir / "logs" / (p.id + ".stats.json");  // merged into the record
  std::vector<std::string> args = {self_executable().string(), "render"};
  for (const std::string& a : p.render_args()) args.push_back(a);
  args.insert(args.end(), {"--threads", "1", "-o", layout.image(p.id, ".exr").string(), "--stats",
                           render_stats.string()});
  if (!p.reference.empty()) args.insert(args.end(), {"--compare", layout.image(p.reference, ".exr").string()});
  const int status = wait_process(start_process(args, layout.log(p.id)));
  // Status 1 is the chip refusing the point with a clear error (a degenerate triangle at
  // an extreme, a fault): a measured outcome, recorded as the row's error. A reference
  // must render, and anything else (a crash) fails the point.
  std::string refused;
  if (status == 1 && !p.reference.empty()) {
    std::ifstream log(layout.log(p.id));
    for (std::string line; std::getline(log, line);) {
      if (line.starts_with("rpu: error: ")) refused = line.substr(12);
    }
  }
  if (status != 0 && refused.empty()) {
    throw Error(fmt::format("{}: `rpu render` exited with status {}; the end of {}:\n{}", p.id, status,
                            layout.log(p.id).string(), tail(layout.log(p.id), 8)));
  }
  const json render = refused.empty() ? read_json(render_stats) : json::object();
  // A NaN in the image makes the comparison NaN, which JSON writes as null: not identical.
  if (refused.empty() && !p.reference.empty() && value_at(render, "compare.max_error").is_null()) {
    refused = "the image has pixels that are not finite numbers";
  }
  if (refused.empty()) write_pictures(layout, p);

  Scene scene = resolve_scene(p.scene);
  const sweep::Transform transform = sweep::parse_transform(p.transform);
  if (transform.scale_exponent != 0) scale_scene(scene, transform.scale_exponent);
  if (transform.offset != 0.0) translate_scene(scene, glm::dvec3(transform.offset));
  json row = {{"id", p.id},
              {"scene", p.scene},
              {"triangles", scene.triangles.size()},
              {"transform", p.transform},
              {"fidelity", p.fidelity},
              {"config", p.config},
              {"set", fmt::format("{}", fmt::join(p.sets, " "))},
              {"format", p.format},
              {"isect", p.isect},
              {"firmware", fmt::format("{}", fmt::join(p.firmware, " "))},
              {"select", p.select},
              {"width", p.width},
              {"height", p.height},
              {"spp", p.spp},
              {"psnr_db", value_at(render, "compare.psnr_db")},
              {"max_error", value_at(render, "compare.max_error")},
              {"dark_dots", value_at(render, "compare.dark_dots")},
              {"self_hits", value_at(render, "rays.self_hits")},
              {"tree_nodes", value_at(render, "tree.nodes")},
              {"nodes_per_ray", per_ray(render, "traversal.nodes")},
              {"tests_per_ray", per_ray(render, "traversal.tests")},
              {"cycles", value_at(render, "cycles")},
              {"fps", value_at(render, "fps")},
              {"rays", value_at(render, "rays.total")},
              {"rays_per_second", value_at(render, "rates.rays_per_second")},
              {"host_seconds", value_at(render, "run.host_seconds")},
              {"error", refused.empty() ? json(nullptr) : json(refused)}};
  json checks = nullptr, area = nullptr;
  if (!p.reference.empty()) {
    ChipOptions chip;
    chip.config = p.config;
    chip.sets = p.sets;
    chip.format = p.format;
    chip.isect = p.isect;
    const KdBuildConfig build = chip.build_config();
    // A transformed scene is measured by its image: its trees can be so costly (a
    // translated mesh in a narrow format) that thousands of check rays take hours.
    const bool checked = p.transform.empty();
    const bool hit_check = checked && plan_hit_check;
    const std::uint32_t leak_rays = checked ? plan_leak_rays : 0;
    const std::uint32_t extreme_rays = checked ? plan_extreme_rays : 0;
    sweep::RayChecks c;
    try {
      c = sweep::check_rays(scene, build, chip.isect_mode(), p.width, p.height, hit_check, leak_rays, p.seed,
                            extreme_rays);
    } catch (const Error&) {
      if (refused.empty()) throw;  // else the units refuse the scene, as the render did
    }
    checks = {{"primary_rays", c.primary_rays},
              {"hit_mismatches", c.hit_mismatches},
              {"closed_meshes", c.closed_meshes},
              {"leak_rays", c.leak_rays},
              {"leaks", c.leaks},
              {"axis_rays", c.axis_rays},
              {"axis_mismatches", c.axis_mismatches},
              {"grazing_rays", c.grazing_rays},
              {"grazing_mismatches", c.grazing_mismatches},
              {"surface_rays", c.surface_rays},
              {"surface_mismatches", c.surface_mismatches}};
    for (const auto& [key, value] : checks.items()) row[key] = value;
    if (!hit_check) row["primary_rays"] = row["hit_mismatches"] = nullptr;
    if (c.closed_meshes == 0) row["leak_rays"] = row["leaks"] = nullptr;
    if (extreme_rays == 0) {
      for (const char* k : {"axis", "grazing", "surface"}) {
        row[fmt::format("{}_rays", k)] = row[fmt::format("{}_mismatches", k)] = nullptr;
      }
    }
    const std::optional<std::uint64_t> datapath = sweep::datapath_cells(build.format, chip.isect_mode());
    const std::optional<std::uint64_t> whole = sweep::chip_cells(p.config, chip.isect_mode());
    row["datapath_cells"] = datapath ? json(*datapath) : json(nullptr);
    // The chip's cells hold for the configuration as named, in its own format, unchanged.
    const bool as_named = p.sets.empty() && fp::format_by_name(config::resolve(p.config).format) == build.format;
    row["chip_cells"] = whole && as_named ? json(*whole) : json(nullptr);
    area = {{"datapath_cells", row["datapath_cells"]}, {"chip_cells", row["chip_cells"]}};
  }
  const json record = {{"id", p.id},
                       {"sweep", sweep_name},
                       {"point", point_json(p)},
                       {"row", row},
                       {"checks", checks},
                       {"area", area},
                       {"images",
                        refused.empty()
                            ? json{{"exr", fmt::format("images/{}.exr", p.id)},
                                   {"png", fmt::format("images/{}.png", p.id)},
                                   {"diff", p.reference.empty() ? json(nullptr)
                                                                : json(fmt::format("images/{}.diff.png", p.id))}}
                            : json(nullptr)},
                       {"render", render}};
  write_text(layout.row(p.id), csv_header() + csv_line(row));
  write_text(layout.record(p.id), record.dump(1) + "\n");  // last: the record marks the point done
  fs::remove(render_stats);  // none when refused
  const json psnr = row["psnr_db"];
  fmt::print("{}: {}{}\n", p.id,
             p.reference.empty()  ? "reference"
             : !refused.empty()   ? "refused: " + refused
             : psnr.is_null()     ? "identical to the reference"
                                  : fmt::format("{:.2f} dB", psnr.get<double>()),
             row.value("leaks", json(nullptr)).is_null() ? "" : fmt::format(", {} leaks", row["leaks"].dump()));
  return 0;
}

// --- rpu sweep -------------------------------------------------------------------------

struct SweepOptions {
  fs::path spec;
  fs::path dir;
  int jobs = 1;
  bool plan_only = false;
};

std::string job_line(const fs::path& exe, const Layout& layout, const std::string& id) {
  return fmt::format("{} sweep-point {} {}\n", shell_word(exe.string()), shell_word(layout.dir.string()),
                     shell_word(id));
}

// The GNU parallel and Slurm files of the job lists.
void write_cluster_files(const Layout& layout, const sweep::Spec& spec, std::size_t references, std::size_t points) {
  write_text(layout.dir / "run-parallel.sh",
             "#!/bin/sh\n"
             "# The sweep through GNU parallel: the references, then the points; JOBS at a time\n"
             "# (default: one per core). Finished points are skipped, so a rerun resumes.\n"
             "set -e\n"
             "cd \"$(dirname \"$0\")\"\n"
             "parallel --jobs \"${JOBS:-100%}\" < jobs/references.txt\n"
             "parallel --jobs \"${JOBS:-100%}\" < jobs/points.txt\n");
  fs::permissions(layout.dir / "run-parallel.sh", fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
  // Slurm's default MaxArraySize is 1001: an array of at most 1000 tasks, each taking
  // every 1000th line.
  for (const auto& [phase, lines] : {std::pair<std::string, std::size_t>{"references", references}, {"points", points}}) {
    if (lines == 0) continue;
    const std::size_t tasks = std::min<std::size_t>(lines, 1000);
    write_text(layout.dir / "slurm" / (phase + ".sbatch"),
               fmt::format("#!/bin/bash\n"
                           "#SBATCH --job-name=rpu-{name}-{phase}\n"
                           "#SBATCH --array=0-{last}\n"
                           "#SBATCH --cpus-per-task=1\n"
                           "#SBATCH --output={dir}/slurm/logs/{phase}-%A_%a.out\n"
                           "# Task i runs lines i+1, i+1+{tasks}, ... of jobs/{phase}.txt.\n"
                           "status=0\n"
                           "for ((i = SLURM_ARRAY_TASK_ID; i < {lines}; i += {tasks})); do\n"
                           "  sed -n \"$((i + 1))p\" {dir}/jobs/{phase}.txt | bash || status=1\n"
                           "done\n"
                           "exit $status\n",
                           fmt::arg("name", spec.name), fmt::arg("phase", phase), fmt::arg("last", tasks - 1),
                           fmt::arg("dir", shell_word(layout.dir.string())), fmt::arg("tasks", tasks),
                           fmt::arg("lines", lines)));
  }
  write_text(layout.dir / "slurm" / "submit.sh",
             "#!/bin/sh\n"
             "# Submits the references, then the points once every reference is done. Arguments go\n"
             "# to both sbatch calls (--partition=..., --wait).\n"
             "set -e\n"
             "cd \"$(dirname \"$0\")\"\n"
             "ref=$(sbatch --parsable \"$@\" references.sbatch)\n"
             + std::string(points == 0 ? "" : "sbatch --parsable --dependency=afterok:\"${ref%%;*}\" \"$@\" points.sbatch\n"));
  fs::permissions(layout.dir / "slurm" / "submit.sh", fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
}

// Runs the phase's points not done yet, `jobs` at a time; returns the ids that failed.
std::vector<std::string> run_phase(const Layout& layout, const std::vector<sweep::Point>& phase, int jobs,
                                   std::size_t& finished, std::size_t total) {
  const fs::path exe = self_executable();
  std::map<pid_t, std::pair<std::string, std::chrono::steady_clock::time_point>> running;
  std::vector<std::string> failed;
  auto reap = [&] {
    int status = 0;
    pid_t pid;
    while ((pid = waitpid(-1, &status, 0)) < 0 && errno == EINTR) {
    }
    if (pid < 0) throw Error(fmt::format("waiting for a point: {}", std::strerror(errno)));
    const auto [id, start] = running.at(pid);
    running.erase(pid);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++finished;
    const fs::path log = layout.dir / "logs" / (id + ".point.log");
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      std::ifstream in(log);
      std::string line;
      std::getline(in, line);
      fmt::print(stderr, "[{}/{}] {} ({:.1f} s)\n", finished, total, line, seconds);
    } else {
      failed.push_back(id);
      fmt::print(stderr, "[{}/{}] {}: FAILED; {}:\n{}", finished, total, id, log.string(), failure_text(log));
    }
  };
  for (const sweep::Point& p : phase) {
    if (done(layout, p.id)) continue;
    while (static_cast<int>(running.size()) >= jobs) reap();
    const pid_t pid =
        start_process({exe.string(), "sweep-point", layout.dir.string(), p.id}, layout.dir / "logs" / (p.id + ".point.log"));
    running.emplace(pid, std::make_pair(p.id, std::chrono::steady_clock::now()));
  }
  while (!running.empty()) reap();
  return failed;
}

// Every point's backend, chip and firmware are checked before any point runs: a point
// that cannot run is an error of the plan that names it, not a "refused" row of a sweep
// that ends well (a refused row is a chip's measured refusal of its scene).
void check_points_run(const sweep::Spec& spec) {
  const device::Registry backends;
  std::set<std::vector<std::string>> firmware_checked;
  for (const auto* list : {&spec.references, &spec.points}) {
    for (const sweep::Point& p : *list) {
      if (p.fidelity == "reference") continue;
      const device::Backend* backend = backends.find(p.fidelity);
      if (backend == nullptr) {
        throw Error(fmt::format("point {}: fidelity {}: this build has no {} backend (it has {})", p.id, p.fidelity,
                                p.fidelity, fmt::join(backends.names(), ", ")));
      }
      ChipOptions chip;
      chip.config = p.config;
      chip.sets = p.sets;
      chip.format = p.format;
      chip.isect = p.isect;
      try {
        backend->check_runs(chip.hardware_config(), chip.number_format(), chip.isect_mode());
      } catch (const Error& e) {
        throw Error(fmt::format("point {}: fidelity {}: {}", p.id, p.fidelity, e.what()));
      }
      if (p.firmware.empty() || !firmware_checked.insert(p.firmware).second) continue;
      try {
        load_firmware(std::vector<fs::path>(p.firmware.begin(), p.firmware.end()));
      } catch (const Error& e) {
        throw Error(fmt::format("point {}: firmware {}: {}", p.id, fmt::join(p.firmware, " "), e.what()));
      }
    }
  }
}

int run_sweep(const SweepOptions& o) {
  const sweep::Spec spec = sweep::read_spec(o.spec);
  check_points_run(spec);
  const Layout layout{fs::absolute(o.dir)};
  for (const char* sub : {"points", "images", "logs", "jobs", "slurm", "slurm/logs"}) {
    std::error_code ec;
    fs::create_directories(layout.dir / sub, ec);
    if (ec) throw Error(fmt::format("-o {}: cannot create {}: {}", o.dir.string(), (layout.dir / sub).string(), ec.message()));
  }
  // One rpu sweep a directory: a second would rewrite the plan and the table under the
  // first. Refused at once; the job lists' sweep-point runs may go on beside it.
  const FileLock lock(layout.sweep_lock(), FileLock::Wait::kNo);
  if (!lock.held()) {
    throw Error(fmt::format("-o {}: another rpu sweep{} is running on this directory; wait for it to end, or give "
                            "another directory",
                            o.dir.string(), lock.holder().empty() ? "" : fmt::format(" (pid {})", lock.holder())));
  }
  json plan = {{"sweep", spec.name},         {"spec", fs::absolute(o.spec).string()},
               {"leak_rays", spec.leak_rays}, {"extreme_rays", spec.extreme_rays}, {"hit_check", spec.hit_check},
               {"references", json::array()}, {"points", json::array()}};
  const fs::path exe = self_executable();
  std::string reference_jobs, point_jobs;
  for (const sweep::Point& p : spec.references) {
    plan["references"].push_back(point_json(p));
    reference_jobs += job_line(exe, layout, p.id);
  }
  for (const sweep::Point& p : spec.points) {
    plan["points"].push_back(point_json(p));
    point_jobs += job_line(exe, layout, p.id);
  }
  write_text(layout.plan(), plan.dump(1) + "\n");
  write_text(layout.dir / "jobs" / "references.txt", reference_jobs);
  write_text(layout.dir / "jobs" / "points.txt", point_jobs);
  write_cluster_files(layout, spec, spec.references.size(), spec.points.size());

  const std::size_t total = spec.references.size() + spec.points.size();
  std::size_t already = 0;
  for (const auto* list : {&spec.references, &spec.points}) {
    for (const sweep::Point& p : *list) already += done(layout, p.id) ? 1 : 0;
  }
  fmt::print(stderr, "rpu: sweep {}: {} points ({} references), {} done already{}\n", spec.name, total,
             spec.references.size(), already,
             o.plan_only ? fmt::format("; job lists in {} (run-parallel.sh, slurm/submit.sh)", layout.dir.string())
                         : fmt::format("; running {} with -j {}", total - already, o.jobs));
  if (o.plan_only) return 0;

  std::size_t finished = already;
  std::vector<std::string> failed = run_phase(layout, spec.references, o.jobs, finished, total);
  if (!failed.empty()) {
    throw Error(fmt::format("{} reference{} failed ({}); the points need them", failed.size(),
                            failed.size() == 1 ? "" : "s", fmt::join(failed, ", ")));
  }
  failed = run_phase(layout, spec.points, o.jobs, finished, total);
  if (!failed.empty()) {
    throw Error(fmt::format("{} of {} points failed: {}; their logs are in {}", failed.size(), total,
                            fmt::join(failed, ", "), (layout.dir / "logs").string()));
  }
  // Every point's row, in the plan's order.
  std::string table = csv_header();
  for (const auto* list : {&spec.references, &spec.points}) {
    for (const sweep::Point& p : *list) table += csv_line(read_json(layout.record(p.id)).at("row"));
  }
  write_text(layout.dir / "sweep.csv", table);
  fmt::print(stderr, "rpu: sweep {}: {} points -> {}\n", spec.name, total, (layout.dir / "sweep.csv").string());
  return 0;
}

}  // namespace

Command add_sweep_command(CLI::App& app) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Run a sweep file's grid of renders (docs/sweeps.md): each point measured against the reference");
  cmd->add_option("spec", options->spec, "The sweep file (TOML)")->required();
  cmd->add_option("-o,--output", options->dir, "The sweep directory: plan, job lists, points, images, sweep.csv")
      ->required();
  cmd->add_option("-j,--jobs", options->jobs, "Points run at once")->check(CLI::Range(1, 1024))->capture_default_str();
  cmd->add_flag("--plan", options->plan_only,
                "Write the plan and the job lists (GNU parallel, Slurm) only; run nothing");
  return {cmd, [options] { return run_sweep(*options); }};
}

Command add_sweep_point_command(CLI::App& app) {
  auto options = std::make_shared<PointOptions>();
  CLI::App* cmd = app.add_subcommand("sweep-point", "Run one point of a planned sweep (the job lists' lines)");
  cmd->add_option("dir", options->dir, "The sweep directory (rpu sweep -o)")->required();
  cmd->add_option("id", options->id, "The point's id (plan.json)")->required();
  return {cmd, [options] { return run_sweep_point(*options); }};
}

}  // namespace rpu::cli
