#include "viewer/frame_pacer.h"

#include <algorithm>

namespace clothsim::viewer {

double FramePacer::simulated_step(double wall_interval) { return std::clamp(wall_interval, 0.0, kLongestFrame); }

void FramePacer::record(double wall_interval, double simulated, bool playing) {
  frames_.push_back({wall_interval, simulated, playing});
  window_wall_ += wall_interval;
  while (frames_.size() > 1 && window_wall_ - frames_.front().wall >= kWindow) {
    window_wall_ -= frames_.front().wall;
    frames_.pop_front();
  }
}

double FramePacer::frames_per_second() const {
  return window_wall_ > 0.0 ? static_cast<double>(frames_.size()) / window_wall_ : 0.0;
}

double FramePacer::real_time_ratio() const {
  double wall = 0.0;
  double simulated = 0.0;
  for (const Frame& frame : frames_) {
    if (!frame.playing) continue;
    wall += frame.wall;
    simulated += frame.simulated;
  }
  return wall > 0.0 ? simulated / wall : 0.0;
}

bool FramePacer::behind() const {
  double playing_wall = 0.0;
  for (const Frame& frame : frames_) {
    if (frame.playing) playing_wall += frame.wall;
  }
  return playing_wall >= 0.25 * kWindow && real_time_ratio() < kBehindRatio;
}

}  // namespace clothsim::viewer
