// A one-line progress display for long runs, redrawn in place on stderr.
//
//   [#########...............]  37.5%  t 7.50/20 s  12034 steps  2.31x real time  ETA 5.4 s
//
// Shown only when stderr is a terminal (a log file or a pipe gets no carriage-return noise) and
// the user did not ask for quiet; redrawn at most ten times a second, so a fast run does not
// spend its time on the terminal.
#pragma once

#include <cstdint>
#include <string>

#include "core/timer.h"

namespace clothsim::cli {

class ProgressBar {
 public:
  // `end_time`: the simulated time at 100 %, s.
  ProgressBar(bool enabled, double end_time);
  ~ProgressBar();

  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Redraws the line if enough wall time has passed since the last redraw.
  void update(double simulated_time, std::uint64_t steps);
  // Erases the line, so that what follows starts on a clean line. Idempotent.
  void clear();

  bool enabled() const { return enabled_; }

 private:
  std::string render(double simulated_time, std::uint64_t steps) const;

  bool enabled_ = false;
  double end_time_ = 0.0;
  Stopwatch wall_;
  double last_draw_ = -1.0;      // wall time of the last redraw, s
  std::size_t drawn_width_ = 0;  // characters on the line now
};

}  // namespace clothsim::cli
