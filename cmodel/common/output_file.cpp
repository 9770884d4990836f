#include "common/output_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <random>
#include <streambuf>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu {

namespace fs = std::filesystem;

namespace {

// The live temporaries, for the signal handlers: fixed storage, because a handler may
// only read memory and call async-signal-safe functions (unlink, write, _exit).
// Claimed and freed under the mutex; a handler reads only `live` and the paths.
constexpr std::size_t kPathBytes = 4096;
struct Slot {
  std::atomic<bool> live{false};
  char temp[kPathBytes];
  char target[kPathBytes];
  char sidecar[kPathBytes];  // empty: none
};
std::array<Slot, 16> slots;
std::mutex slots_mutex;
const char* sigbus_program = nullptr;

void remove_live_temporaries() {
  for (Slot& s : slots) {
    if (!s.live.load(std::memory_order_acquire)) continue;
    ::unlink(s.temp);
    if (s.sidecar[0] != '\0') ::unlink(s.sidecar);
  }
}

// The first fatal signal removes the temporaries; one that arrives meanwhile, on another
// thread (a library's worker), waits until they are gone instead of ending the process
// half way. Either way the process then dies of its signal (status 128 + sig): the
// default action restored, the signal raised on this thread, where the handler's mask
// blocks it until the handler returns.
std::atomic<bool> cleaning{false};
std::atomic<bool> cleaned{false};
static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler may use only lock-free atomics");

void on_fatal_signal(int sig) {
  if (!cleaning.exchange(true)) {
    remove_live_temporaries();
    cleaned.store(true);
  }
  while (!cleaned.load()) {
  }
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void write_stderr(const char* text) {
  for (std::size_t left = std::strlen(text); left > 0;) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<std::size_t>(n);
  }
}

void on_sigbus(int) {
  bool any = false;
  for (Slot& s : slots) {
    if (!s.live.load(std::memory_order_acquire)) continue;
    any = true;
    write_stderr(sigbus_program);
    write_stderr(": ");
    write_stderr(s.target);
    write_stderr(": cannot write the file: bus error in a memory-mapped write, most likely no space left on the "
                 "device; the file was left as it was\n");
  }
  remove_live_temporaries();
  // No output being written: a bug, not a full disk. The default action (restored by
  // SA_RESETHAND) dumps core when the faulting access runs again.
  if (any) ::_exit(2);
}

constexpr int kFatalSignals[] = {SIGINT, SIGTERM, SIGHUP};

// `reset`: the default action comes back when the handler runs (SIGBUS, which must not
// loop). The fatal signals' handler blocks all three on its thread while it runs.
void install(int sig, void (*handler)(int), bool reset) {
  struct sigaction old {};
  ::sigaction(sig, nullptr, &old);
  // An ignored signal (nohup) or the program's own handler is left alone.
  if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) return;
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  for (int fatal : kFatalSignals) sigaddset(&sa.sa_mask, fatal);
  sa.sa_flags = reset ? SA_RESETHAND : 0;
  ::sigaction(sig, &sa, nullptr);
}

void install_signal_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : kFatalSignals) install(sig, on_fatal_signal, false);
    struct sigaction old {};
    ::sigaction(SIGXFSZ, nullptr, &old);
    if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_DFL) ::signal(SIGXFSZ, SIG_IGN);
  });
}

int claim_slot(const fs::path& temp, const fs::path& target) {
  const std::string t = temp.string(), g = target.string();
  if (t.size() >= kPathBytes || g.size() >= kPathBytes) {
    throw Error(fmt::format("{}: the path is longer than {} bytes", g, kPathBytes - 1));
  }
  const std::lock_guard lock(slots_mutex);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    Slot& s = slots[i];
    if (s.live.load(std::memory_order_relaxed)) continue;
    std::memcpy(s.temp, t.c_str(), t.size() + 1);
    std::memcpy(s.target, g.c_str(), g.size() + 1);
    s.sidecar[0] = '\0';
    s.live.store(true, std::memory_order_release);
    return static_cast<int>(i);
  }
  throw Error(fmt::format("{}: more than {} output files open at once", g, slots.size()));
}

// Six random letters, so that two writers of one target never share a temporary.
std::string random_tag() {
  static constexpr char kLetters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  const std::lock_guard lock(slots_mutex);
  static std::mt19937_64 rng{std::random_device{}()};
  std::uniform_int_distribution<std::size_t> letter(0, sizeof kLetters - 2);
  std::string tag(6, ' ');
  for (char& c : tag) c = kLetters[letter(rng)];
  return tag;
}

fs::path directory_of(const fs::path& file) { return file.has_parent_path() ? file.parent_path() : fs::path("."); }

// Writes through a symbolic link replace the file it names, not the link.
fs::path resolved(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(file, ec))) return file;
  const fs::path real = fs::weakly_canonical(file, ec);
  return ec ? file : real;
}

}  // namespace

void check_output_path(const fs::path& file) {
  if (!file.has_filename()) throw Error(fmt::format("'{}': an output needs a file name", file.string()));
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (fs::is_directory(st)) throw Error(fmt::format("{}: is a directory; give the output a file name", file.string()));
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    throw Error(fmt::format("{}: not a regular file; outputs are written beside the target and renamed over it, "
                            "so give the path of a file",
                            file.string()));
  }
  const fs::path dir = directory_of(resolved(file));
  if (!fs::is_directory(dir, ec)) {
    throw Error(fmt::format("{}: the directory '{}' does not exist; create it or choose another path", file.string(),
                            dir.string()));
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw Error(fmt::format("{}: cannot create files in '{}': {}", file.string(), dir.string(), std::strerror(errno)));
  }
}

// A stream buffer over the temporary's descriptor that keeps the first write error's
// errno: std::ofstream only reports that something failed, not ENOSPC or EFBIG.
class OutputFile::Buffer final : public std::streambuf {
 public:
  explicit Buffer(int fd) : fd_(fd), data_(std::size_t{1} << 16) { setp(data_.data(), data_.data() + data_.size()); }
  int error() const { return error_; }
  std::uint64_t written() const { return written_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    if (error_ != 0) return false;
    for (const char* p = pbase(); p < pptr();) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        error_ = errno;
        return false;
      }
      p += n;
      written_ += static_cast<std::uint64_t>(n);
    }
    setp(data_.data(), data_.data() + data_.size());
    return true;
  }

  int fd_;
  std::vector<char> data_;
  int error_ = 0;
  std::uint64_t written_ = 0;
};

OutputFile::OutputFile(fs::path target) : target_(std::move(target)) {
  check_output_path(target_);
  install_signal_handlers();
  const fs::path real = resolved(target_);
  std::error_code ec;
  replaces_ = fs::exists(real, ec);
  // Hidden, named after the target, and ending in its extension. The signal handlers
  // know the name before the file exists, so no signal can leave it behind.
  for (int attempt = 0; fd_ < 0; ++attempt) {
    temp_ = directory_of(real) /
            fmt::format(".{}.{}{}", real.filename().string(), random_tag(), real.extension().string());
    slot_ = claim_slot(temp_, target_);
    // 0666 less the umask, as a file the tool created directly would have.
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    const int error = errno;
    if (fd_ < 0) {
      free_slot();
      if (error != EEXIST || attempt == 100) {
        throw Error(fmt::format("{}: cannot create a temporary file beside it: {}", target_.string(),
                                std::strerror(error)));
      }
    }
  }
}

OutputFile::~OutputFile() { release(); }

void OutputFile::release() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!committed_) ::unlink(temp_.c_str());
  if (!sidecar_.empty()) ::unlink(sidecar_.c_str());
  free_slot();
}

void OutputFile::free_slot() {
  if (slot_ >= 0) {
    const std::lock_guard lock(slots_mutex);
    slots[static_cast<std::size_t>(slot_)].live.store(false, std::memory_order_release);
  }
  slot_ = -1;
}

void OutputFile::add_sidecar(const fs::path& file) {
  const std::string path = file.string();
  if (path.size() >= kPathBytes) throw Error(fmt::format("{}: the path is longer than {} bytes", path, kPathBytes - 1));
  sidecar_ = file;
  const std::lock_guard lock(slots_mutex);
  Slot& s = slots[static_cast<std::size_t>(slot_)];
  // Hidden from the handler while it changes.
  s.live.store(false, std::memory_order_release);
  std::memcpy(s.sidecar, path.c_str(), path.size() + 1);
  s.live.store(true, std::memory_order_release);
}

std::ostream& OutputFile::stream() {
  if (!stream_) {
    buffer_ = std::make_unique<Buffer>(fd_);
    stream_ = std::make_unique<std::ostream>(buffer_.get());
  }
  return *stream_;
}

void OutputFile::fail(const std::string& reason) {
  release();
  throw Error(fmt::format("{}: cannot write the file: {}; {}", target_.string(), reason,
                          replaces_ ? "the previous file is unchanged" : "no file was written"));
}

void OutputFile::commit() {
  if (stream_) {
    stream_->flush();
    if (buffer_->error() != 0) fail(std::strerror(buffer_->error()));
    if (!*stream_) fail("a write to the stream failed");
  }
  // A library may have replaced the temporary (the FST writer unlinks and recreates
  // it): check the file by its name.
  const int fd = stream_ ? fd_ : ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(fmt::format("the temporary {} is gone: {}", temp_.string(), std::strerror(errno)));
  struct stat st {};
  const bool synced = ::fsync(fd) == 0 && ::fstat(fd, &st) == 0;
  const int sync_error = errno;
  if (fd != fd_) ::close(fd);
  if (!synced) fail(std::strerror(sync_error));
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (stream_ && size != buffer_->written()) {
    fail(fmt::format("{} bytes on disk of the {} written", size, buffer_->written()));
  }
  if (!stream_ && size == 0) fail("nothing was written to it");
  const int closed = ::close(fd_);
  const int close_error = errno;
  fd_ = -1;
  if (closed != 0) fail(std::strerror(close_error));
  const fs::path real = resolved(target_);
  struct stat old {};
  // A replaced file keeps its permissions.
  if (replaces_ && ::stat(real.c_str(), &old) == 0) ::chmod(temp_.c_str(), old.st_mode & 07777);
  if (::rename(temp_.c_str(), real.c_str()) != 0) fail(std::strerror(errno));
  committed_ = true;
  // The rename is durable once the directory is synced; the file is complete either way.
  const int dir = ::open(directory_of(real).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  release();
}

void report_sigbus_as_write_failure(const char* program) {
  sigbus_program = program;
  install(SIGBUS, on_sigbus, true);
}

}  // namespace rpu
