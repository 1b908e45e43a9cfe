// Real-time pacing of the interactive viewer: simulated time follows wall time.
//
// Each displayed frame asks the simulation to advance by the wall time since the previous frame
// (capped at kLongestFrame, so a window that was dragged or a debugger stop does not ask for
// seconds of catch-up), within a wall-time budget for simulation work (kWorkBudget), so the
// window keeps answering input when the simulation is too slow for real time. Time that does
// not fit in the budget is dropped rather than owed: the simulation then runs slower than real
// time, and says so, instead of falling ever further behind.
//
// The readouts are averages over the last second of frames: frames per second, and simulated
// seconds per wall second while playing (1.0 when the simulation keeps up). The viewer shows the
// ratio in red below kBehindRatio. FrameBenchmark measures the same over a run of
// --benchmark-frames and prints it.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "core/timer.h"
#include "sim/simulation.h"

namespace clothsim::viewer {

class FramePacer {
 public:
  static constexpr double kLongestFrame = 0.1;   // s of wall time one frame may simulate
  static constexpr double kWorkBudget = 0.025;   // s of wall time per frame for the simulation
  static constexpr double kPiece = 1.0 / 240.0;  // s, simulated time per advance_to between budget checks
  static constexpr double kBehindRatio = 0.95;   // below this, the simulation is behind real time
  static constexpr double kWindow = 1.0;         // s of wall time the readouts average over

  // Simulated time the next frame should advance after `wall_interval` s since the last frame.
  static double simulated_step(double wall_interval);

  // Records a finished frame: the wall time since the previous frame, the simulated time it
  // advanced and whether the simulation was playing.
  void record(double wall_interval, double simulated, bool playing);

  double frames_per_second() const;
  // Simulated seconds per wall second over the playing frames of the window; 0 without any.
  double real_time_ratio() const;
  // Playing, with enough of a window to judge, and slower than kBehindRatio.
  bool behind() const;

 private:
  struct Frame {
    double wall = 0.0;
    double simulated = 0.0;
    bool playing = false;
  };
  std::deque<Frame> frames_;
  double window_wall_ = 0.0;  // sum of frames_[i].wall
};

// The figures of --benchmark-frames: frames per second, the median frame, simulated time per
// wall time, and how a frame's wall time splits between simulating and the rest.
class FrameBenchmark {
 public:
  // Starts the wall clock (after the first frame, whose interval holds the start-up).
  void start() { clock_.restart(); }
  // Records a measured frame: its wall interval, the simulated time it advanced, and the wall
  // time the simulation took, s.
  void record(double wall_interval, double simulated, double simulation_seconds);
  // Prints the figures to stdout for `scene`'s `simulation` in a window of `window` pixels
  // ("1280x800"); nothing without a measured frame.
  void print(const std::string& scene, const Simulation& simulation, const std::string& window) const;

 private:
  Stopwatch clock_;
  double simulated_ = 0.0;           // s, simulated over the measured frames
  double simulation_seconds_ = 0.0;  // s of wall time spent in Session::advance
  std::vector<double> intervals_;    // s, wall time of each measured frame
};

}  // namespace clothsim::viewer
