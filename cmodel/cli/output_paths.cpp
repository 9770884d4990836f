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

// A file named on the command line: the option's names (without dashes) and how to
// call it in a message.
struct GivenFile {
  std::vector<std::string> names;
  std::string what;
  fs::path path;
};
std::vector<GivenFile> given_files;

// `option` as PlannedOutput spells it ("-o", "--stats") is one of the names.
bool names(const GivenFile& f, std::string_view option) {
  const std::size_t dashes = option.find_first_not_of('-');
  if (dashes == 0 || dashes == std::string_view::npos) return false;
  return std::find(f.names.begin(), f.names.end(), option.substr(dashes)) != f.names.end();
}

std::string alternatives(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i) text += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
  return text;
}

}  // namespace

void note_command_line_files(const CLI::App& command) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0) continue;
    GivenFile given;
    given.names = option->get_lnames();
    for (const std::string& s : option->get_snames()) given.names.push_back(s);
    given.what = option->get_positional() ? "the " + option->get_name() : option->get_name();
    for (const std::string& value : option->results()) {
      std::error_code ec;
      if (!fs::is_regular_file(value, ec)) continue;
      given.path = value;
      given_files.push_back(given);
    }
  }
  for (const CLI::App* sub : command.get_subcommands()) note_command_line_files(*sub);
}

void check_outputs(const std::vector<PlannedOutput>& outputs, const std::vector<PlannedInput>& planned) {
  std::vector<PlannedInput> inputs = planned;
  for (const GivenFile& f : given_files) {
    const bool is_output = std::any_of(outputs.begin(), outputs.end(), [&](const PlannedOutput& o) {
      return names(f, o.option);
    });
    if (!is_output) inputs.push_back({f.what, f.path});
  }
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
