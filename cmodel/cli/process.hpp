#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

// Child processes of the CLI: the points of a sweep, the report's plotting program.
namespace rpu::cli {

// Starts args[0] (a path) with args; its stdout and stderr go to `log` (truncated), or
// are inherited when `log` is empty. Throws rpu::Error if it cannot be started.
pid_t start_process(const std::vector<std::string>& args, const std::filesystem::path& log);

// Waits for `pid`; its exit status, or 128 + the signal that ended it.
int wait_process(pid_t pid);

// Runs args and returns what it wrote to stdout (stderr is inherited) and its status.
struct Captured {
  std::string out;
  int status = 0;
};
Captured capture_process(const std::vector<std::string>& args);

// The path of the running executable (/proc/self/exe).
std::filesystem::path self_executable();

}  // namespace rpu::cli
