#include "cli/progress.hpp"

#include <cstdio>

#include <fmt/format.h>
#include <unistd.h>

namespace rpu::cli {

namespace {
constexpr int kBarWidth = 30;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

std::string format_seconds(double s) {
  if (s < 60.0) return fmt::format("{:.1f}s", s);
  return fmt::format("{}m{:02}s", static_cast<int>(s / 60.0), static_cast<int>(s) % 60);
}
}  // namespace

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)), enabled_(isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  if (drawn_) std::fputs("\r\033[K", stderr);  // leave the line to the summary
}

void ProgressBar::update(std::size_t done, std::size_t total) {
  if (!enabled_ || total == 0) return;
  const std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (done < total && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  const double fraction = static_cast<double>(done) / static_cast<double>(total);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const int filled = static_cast<int>(fraction * kBarWidth);
  const std::string eta = done > 0 ? format_seconds(elapsed * (1.0 - fraction) / fraction) : "?";
  fmt::print(stderr, "\r\033[K{} [{}{}] {:3.0f}%  {} elapsed, ETA {}", label_, std::string(filled, '#'),
             std::string(kBarWidth - filled, ' '), 100.0 * fraction, format_seconds(elapsed), eta);
  std::fflush(stderr);
  drawn_ = true;
}

std::string millions(std::uint64_t n) { return fmt::format("{:.2f} M", static_cast<double>(n) * 1e-6); }

}  // namespace rpu::cli
