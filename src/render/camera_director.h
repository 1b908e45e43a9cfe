// Chooses the camera for each frame of a recorded run (images and video of `clothsim run`).
//
// Modes (`--camera`):
//   automatic  frames the bounding box of every position seen so far in the run (fit() from a
//              fixed direction). The box only grows, so the camera never moves back and forth:
//              a sheet that hangs or drapes gets a steady shot, and one that falls is followed
//              by a smooth zoom out. Default.
//   follow     keeps the current sheet framed: target and distance move towards the current
//              frame's fit with an exponential low-pass of time constant `follow_time` (simulated
//              seconds), so the camera glides after a falling sheet without jitter. A low-pass
//              lags an accelerating sheet (by speed x follow_time), so the distance never drops
//              below what keeps the current frame in view from the lagging target.
//   fixed      a given distance: the target is the centre of the first frame's bounding box
//              and nothing moves.
// The direction (azimuth, elevation) is fixed in every mode, so lighting stays put too. Bounded
// colliders (spheres, boxes, capsules, meshes; not planes) count as seen, where they are at the
// frame's time, so the obstacle a sheet drapes over is in the picture.
//
// The ground height follows the same rule as automatic framing: below the lowest point seen so
// far (model spacing or 5% of the sheet below it), so it never jumps up.
//
// Rejected: framing each frame on its own (the picture pumps as the sheet swings), and framing
// the whole run (needs the run's future: a second pass over positions.npy).
#pragma once

#include <optional>
#include <span>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "render/camera.h"

namespace clothsim::render {

enum class CameraMode { automatic, follow, fixed };

struct CameraChoice {
  CameraMode mode = CameraMode::automatic;
  double azimuth = 0.6109;    // rad (35 degrees): from the front right
  double elevation = 0.4363;  // rad (25 degrees) above the horizon
  double distance = 0.0;      // m, for CameraMode::fixed
  double follow_time = 0.25;  // s of simulated time, for CameraMode::follow
};

class CameraDirector {
 public:
  CameraDirector(const CameraChoice& choice, double aspect);

  // The camera and ground height for the frame at simulated time `time` (s) with particle
  // positions `position` (m). Frames come in time order; non-finite positions are ignored.
  void update(const ClothModel& model, std::span<const Vec3> position, double time);

  const Camera& camera() const { return camera_; }
  double ground_height() const { return ground_height_; }

 private:
  CameraChoice choice_;
  double aspect_;
  Camera camera_;
  bool started_ = false;
  double last_time_ = 0.0;
  Vec3 low_;  // bounding box of everything seen so far
  Vec3 high_;
  double ground_height_ = 0.0;
};

}  // namespace clothsim::render
