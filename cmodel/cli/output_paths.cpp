#include "cli/output_paths.hpp"

#include <algorithm>
#include <system_error>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/output_file.hpp"

namespace rpu::cli {

namespace fs = std::filesystem;

namespace {

// One file under two names: the same path once symbolic links and ".." are resolved,
// or, when both exist, the same inode (a hard link).
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

std::string alternatives(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i) text += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
  return text;
}

}  // namespace

void check_outputs(const std::vector<PlannedOutput>& outputs, const std::vector<PlannedInput>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const PlannedOutput& o = outputs[i];
    for (const PlannedInput& in : inputs) {
      if (same_file(o.path, in.path)) {
        throw Error(fmt::format("{} {}: the same file as {} {}, which it would overwrite; choose another output path",
                                o.option, o.path.string(), in.what, in.path.string()));
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (same_file(o.path, outputs[j].path)) {
        throw Error(fmt::format("{} {} and {} {}: the same file twice, one would overwrite the other; give each "
                                "output its own path",
                                outputs[j].option, outputs[j].path.string(), o.option, o.path.string()));
      }
    }
    const std::string ext = o.path.extension().string();
    if (!o.extensions.empty() && std::find(o.extensions.begin(), o.extensions.end(), ext) == o.extensions.end()) {
      throw Error(fmt::format("{} {}: unknown file type '{}', expected {}", o.option, o.path.string(), ext,
                              alternatives(o.extensions)));
    }
    try {
      check_output_path(o.path);
    } catch (const Error& e) {
      throw Error(fmt::format("{} {}", o.option, e.what()));
    }
  }
}

}  // namespace rpu::cli
