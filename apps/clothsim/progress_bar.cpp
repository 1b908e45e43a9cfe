#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli_support.h"

namespace clothsim::cli {
namespace {

constexpr double kRedrawInterval = 0.1;  // s of wall time
constexpr int kBarWidth = 24;            // characters between the brackets

}  // namespace

ProgressBar::ProgressBar(bool enabled, double end_time)
    : enabled_(enabled && ::isatty(STDERR_FILENO) == 1), end_time_(end_time) {}

ProgressBar::~ProgressBar() { clear(); }

void ProgressBar::update(double simulated_time, std::uint64_t steps) {
  if (!enabled_) return;
  const double now = wall_.seconds();
  if (last_draw_ >= 0.0 && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  const std::string line = render(simulated_time, steps);
  // Pad with spaces over the end of a longer previous line.
  const std::size_t padding = drawn_width_ > line.size() ? drawn_width_ - line.size() : 0;
  std::fprintf(stderr, "\r%s%*s", line.c_str(), static_cast<int>(padding), "");
  std::fflush(stderr);
  drawn_width_ = line.size();
}

void ProgressBar::clear() {
  if (!enabled_ || drawn_width_ == 0) return;
  std::fprintf(stderr, "\r%*s\r", static_cast<int>(drawn_width_), "");
  std::fflush(stderr);
  drawn_width_ = 0;
}

std::string ProgressBar::render(double simulated_time, std::uint64_t steps) const {
  const double fraction = end_time_ > 0.0 ? std::clamp(simulated_time / end_time_, 0.0, 1.0) : 1.0;
  const int filled = static_cast<int>(fraction * kBarWidth);
  std::string line = "[";
  line.append(static_cast<std::size_t>(filled), '#');
  line.append(static_cast<std::size_t>(kBarWidth - filled), '.');
  line += ']';

  const double wall = wall_.seconds();
  const double realtime_factor = wall > 0.0 ? simulated_time / wall : 0.0;
  const double eta = fraction > 0.0 ? wall * (1.0 - fraction) / fraction : NAN;
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, " %5.1f%%  t %s/%s s  %llu steps  %.3gx real time  ETA %s", 100.0 * fraction,
                format_number_short(simulated_time).c_str(), format_number_short(end_time_).c_str(),
                static_cast<unsigned long long>(steps), realtime_factor,
                std::isfinite(eta) ? format_duration(eta).c_str() : "?");
  line += numbers;
  return line;
}

}  // namespace clothsim::cli
