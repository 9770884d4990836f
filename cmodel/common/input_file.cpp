#include "common/input_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>

#include <sys/stat.h>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu {
namespace {

std::string named(const std::filesystem::path& file, std::string_view what) {
  return what.empty() ? file.string() : fmt::format("{} {}", what, file.string());
}

// What a file that is not regular is, in the words of ls and stat.
const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "not a regular file";
}

}  // namespace

void check_input_file(const std::filesystem::path& file, std::string_view what) {
  // stat(2), not std::filesystem: its errors are exceptions or codes without the path,
  // and a FIFO must be recognised without opening it (open blocks until a writer comes).
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) throw Error(fmt::format("{}: no such file", named(file, what)));
    if (err == ELOOP) throw Error(fmt::format("{}: a loop of symbolic links", named(file, what)));
    throw Error(fmt::format("{}: cannot be examined: {}", named(file, what), std::strerror(err)));
  }
  if (!S_ISREG(st.st_mode)) {
    throw Error(fmt::format("{}: {}; the tools read only regular files", named(file, what), kind_of(st.st_mode)));
  }
}

std::string read_input_file(const std::filesystem::path& file, std::string_view what, std::uintmax_t max_bytes) {
  check_input_file(file, what);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open: {}", named(file, what), std::strerror(errno)));
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (!ec && size > max_bytes) {
    throw Error(fmt::format("{}: {} bytes, more than the {} this input may have", named(file, what), size, max_bytes));
  }
  std::string bytes;
  try {
    if (!ec) bytes.reserve(static_cast<std::size_t>(size));
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
      bytes.append(buffer, static_cast<std::size_t>(in.gcount()));
      if (bytes.size() > max_bytes) {
        throw Error(fmt::format("{}: more than the {} bytes this input may have", named(file, what), max_bytes));
      }
    }
  } catch (const std::bad_alloc&) {
    throw Error(fmt::format("{}: too large to read into memory", named(file, what)));
  } catch (const std::ios_base::failure& e) {
    throw Error(fmt::format("{}: cannot read: {}", named(file, what), e.what()));
  }
  if (in.bad()) throw Error(fmt::format("{}: cannot read: {}", named(file, what), std::strerror(errno)));
  return bytes;
}

}  // namespace rpu
