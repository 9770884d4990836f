// rpu report: a sweep directory as one self-contained HTML page, or as a generated block
// of a Markdown page with its pictures beside it (docs/sweeps.md, "Reports"). The plots
// are matplotlib's, drawn by cmodel/sweep/report.py, which is built into the binary with
// the docs' block filler it imports (spec/doc_blocks.py).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "cli/process.hpp"
#include "common/error.hpp"
#include "common/output_file.hpp"
#include "sweep/report_script.hpp"

namespace rpu::cli {
namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  fs::path dir;
  fs::path output;
};

// Debian's interpreter, where python3-matplotlib is; RPU_PYTHON names another.
std::string python() {
  if (const char* chosen = std::getenv("RPU_PYTHON"); chosen != nullptr && *chosen != '\0') return chosen;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

// The plotting program and the module it imports, written to a directory of their own for
// as long as the report runs.
class ReportProgram {
 public:
  ReportProgram() {
    const std::string pattern = (fs::temp_directory_path() / "rpu-report-XXXXXX").string();
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    if (mkdtemp(name.data()) == nullptr) {
      throw Error(fmt::format("{}: cannot make a directory for the report's program", pattern));
    }
    dir_ = name.data();
    write(dir_ / "report.py", sweep::kReportScript);
    write(dir_ / "doc_blocks.py", sweep::kDocBlocksModule);
  }
  ~ReportProgram() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  ReportProgram(const ReportProgram&) = delete;
  ReportProgram& operator=(const ReportProgram&) = delete;
  fs::path script() const { return dir_ / "report.py"; }

 private:
  static void write(const fs::path& file, std::string_view text) {
    std::ofstream out(file, std::ios::binary);
    out << text;
    if (!out.flush()) throw Error(fmt::format("{}: cannot write the report's program", file.string()));
  }
  fs::path dir_;
};

int run_report(const ReportOptions& o) {
  check_outputs({{"-o", o.output, {".html", ".md"}}}, {});
  if (!fs::is_regular_file(o.dir / "plan.json")) {
    throw Error(fmt::format("{}: not a sweep directory (no plan.json; rpu sweep SPEC -o DIR makes one)", o.dir.string()));
  }
  const bool html = o.output.extension() == ".html";
  const ReportProgram program;
  std::vector<std::string> args = {python(), program.script().string(), o.dir.string(), html ? "html" : "md"};
  // Markdown: the pictures go to a directory named as the page, beside it.
  const fs::path pictures = o.output.parent_path() / o.output.stem();
  if (!html) {
    args.insert(args.end(), {pictures.string(), o.output.stem().string(), o.output.string(),
                             fmt::format("rpu report {} -o {}", o.dir.string(), o.output.string())});
  }
  const Captured result = capture_process(args);
  if (result.status == 2) return 1;  // a page it cannot fill: the program said why
  if (result.status != 0) {
    throw Error(fmt::format("the report's plotting program ({} with matplotlib) failed with status {}, its "
                            "message above; it needs python3-matplotlib (scripts/setup installs it; RPU_PYTHON "
                            "names another python) and a sweep directory rpu sweep wrote",
                            args[0], result.status));
  }
  OutputFile out(o.output);
  out.stream() << result.out;
  out.commit();
  fmt::print(stderr, "rpu: report of {} -> {}{}\n", o.dir.string(), o.output.string(),
             html ? "" : fmt::format(" (pictures and rows.json in {})", pictures.string()));
  return 0;
}

}  // namespace

Command add_report_command(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "A sweep's tables and plots: one self-contained HTML page, or the "
                                               "generated block of a Markdown page");
  cmd->add_option("dir", options->dir, "The sweep directory (rpu sweep -o)")->required();
  cmd->add_option("-o,--output", options->output,
                  "report.html (self-contained), or PAGE.md (its generated block replaced; pictures in PAGE/)")
      ->required();
  return {cmd, [options] { return run_report(*options); }};
}

}  // namespace rpu::cli
