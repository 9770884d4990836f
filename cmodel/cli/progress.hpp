#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace rpu::cli {

// A progress bar with elapsed time and ETA on stderr, drawn only when stderr is a
// terminal (so logs and CI output stay clean). Safe to call from several threads.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::size_t done, std::size_t total);

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_{};
  std::mutex mutex_;
};

// "1.23 M": counts in the closing lines of the commands.
std::string millions(std::uint64_t n);

}  // namespace rpu::cli
