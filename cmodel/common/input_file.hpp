#pragma once

#include <filesystem>
#include <string>
#include <string_view>

// Every file a tool reads is checked here first, so that no input can block a read
// forever (a FIFO, a terminal), read as something it is not (a directory, a device) or
// end in an internal error (a loop of symbolic links, a read that fails half way).
namespace rpu {

// Throws rpu::Error "FILE: <what is wrong>" unless `file` names a regular file, after
// following symbolic links: missing, a directory, a FIFO, a socket, a device, a loop of
// links or a path that cannot be examined. `what` names the input in the message ("the
// scene file"); empty: the message names only the path.
void check_input_file(const std::filesystem::path& file, std::string_view what = {});

// The whole of `file` after check_input_file: a read that fails, or a file larger than
// `max_bytes` or than memory allows, is an rpu::Error naming it.
std::string read_input_file(const std::filesystem::path& file, std::string_view what = {},
                            std::uintmax_t max_bytes = std::uintmax_t{1} << 32);

}  // namespace rpu
