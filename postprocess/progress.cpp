#include "progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace freestand {

std::string format_duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  if (s >= 3600) return fmt::format("{} h {:02d} min", s / 3600, static_cast<int>((s % 3600) / 60));
  if (s >= 60) return fmt::format("{} min {:02d} s", s / 60, static_cast<int>(s % 60));
  return fmt::format("{} s", s);
}

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()), terminal_(isatty(STDERR_FILENO)) {}

void ProgressBar::update(long done, long total) {
  if (total <= 0) return;
  const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // ETA from the mean rate so far: runs go at a steady pace per step.
  const std::string eta = fraction > 0 ? format_duration(elapsed * (1 - fraction) / fraction) : "?";
  if (terminal_) {
    if (elapsed - last_draw_ < 0.2 && fraction < 1) return;  // 5 redraws a second are plenty
    last_draw_ = elapsed;
    const int width = 30, filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r%s [%s%s] %3.0f %%  elapsed %s  ETA %s   ", label_.c_str(),
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), 100 * fraction,
                 format_duration(elapsed).c_str(), eta.c_str());
  } else {
    const int decile = static_cast<int>(10 * fraction);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s %3d %%  elapsed %s  ETA %s\n", label_.c_str(), 10 * decile,
                 format_duration(elapsed).c_str(), eta.c_str());
  }
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (terminal_) std::fprintf(stderr, "\n");
}

}  // namespace freestand
