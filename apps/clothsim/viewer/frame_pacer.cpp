#include "viewer/frame_pacer.h"

#include <algorithm>
#include <cstdio>

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

void FrameBenchmark::record(double wall_interval, double simulated, double simulation_seconds) {
  simulated_ += simulated;
  simulation_seconds_ += simulation_seconds;
  intervals_.push_back(wall_interval);
}

void FrameBenchmark::print(const std::string& scene, const Simulation& simulation, const std::string& window) const {
  if (intervals_.empty()) return;
  const double wall = clock_.seconds();
  std::vector<double> sorted = intervals_;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const auto frames = static_cast<double>(intervals_.size());
  std::printf(
      "benchmark: %s, %dx%d lattice (%zu particles), %s, window %s\n"
      "benchmark: %zu frames in %.3f s: %.1f fps (median frame %.2f ms); simulated %.3f s, %.3fx real time\n"
      "benchmark: per frame %.2f ms simulating, %.2f ms drawing, the panel and the rest\n",
      scene.c_str(), simulation.model().rows, simulation.model().cols, simulation.model().particle_count(),
      std::string(to_string(simulation.settings().integrator.kind)).c_str(), window.c_str(), intervals_.size(), wall,
      frames / wall, 1e3 * median, simulated_, simulated_ / wall, 1e3 * simulation_seconds_ / frames,
      1e3 * (wall - simulation_seconds_) / frames);
  std::fflush(stdout);
}

}  // namespace clothsim::viewer
