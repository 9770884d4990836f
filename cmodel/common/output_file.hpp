#pragma once

#include <filesystem>
#include <memory>
#include <ostream>
#include <string>

// Every file a tool writes goes through OutputFile, so that a full disk, a file-size
// limit or an interrupt never leaves a truncated file where a good one was.
namespace rpu {

// Throws rpu::Error naming `file` unless a file can be created there: its directory
// exists and is writable, and `file` is not a directory or another non-regular file.
// Lets a tool reject a bad output path before hours of work.
void check_output_path(const std::filesystem::path& file);

// One output file, written whole or not at all. The bytes go to a hidden temporary
// beside the target (the same file system, so the rename is atomic); commit() checks
// every write, fsyncs and renames it over the target. On any failure, and on
// destruction without commit(), the temporary is removed and the target keeps its old
// contents. SIGINT, SIGTERM and SIGHUP remove every live temporary before the process
// dies of the signal; SIGXFSZ is ignored, so a file-size limit fails the write (EFBIG)
// and is reported like a full disk.
class OutputFile {
 public:
  // Creates the temporary; rpu::Error naming the target if it cannot.
  explicit OutputFile(std::filesystem::path target);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::filesystem::path& target() const { return target_; }
  // The temporary, for a library that opens its file by name (OpenImageIO, Verilator's
  // FST writer). It ends in the target's extension, by which such libraries pick the
  // format. Use either this or stream(), not both.
  const std::filesystem::path& temp_path() const { return temp_; }
  // A file the library writing temp_path() keeps beside it while it works (the FST
  // writer's "<temp>.hier"): removed with the temporary on failure or a signal.
  void add_sidecar(const std::filesystem::path& file);
  // The temporary as a stream; the first failed write is reported by commit().
  std::ostream& stream();
  // Flushes, fsyncs, checks the size on disk and renames the temporary over the target.
  // rpu::Error naming the target and the system's reason ("No space left on device").
  void commit();
  // Removes the temporary and throws rpu::Error naming the target and `reason`: for a
  // caller's own check of the written file (an image that does not read back).
  [[noreturn]] void fail(const std::string& reason);

 private:
  class Buffer;
  void release();
  // The signal handlers forget the temporary.
  void free_slot();

  std::filesystem::path target_, temp_, sidecar_;
  bool replaces_ = false;  // the target exists: messages say it is unchanged
  int fd_ = -1;
  int slot_ = -1;  // in the signal handler's table of live temporaries
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
  bool committed_ = false;
};

// For programs whose libraries write through memory-mapped files (the co-simulation
// harnesses' FST writer): a store the full disk cannot back raises SIGBUS, which would
// kill the process with a half file. After this call a SIGBUS prints
// "<program>: <target>: cannot write the file: ..." for every live output (the
// harnesses' error format), removes their temporaries and exits with status 2.
void report_sigbus_as_write_failure(const char* program);

}  // namespace rpu
