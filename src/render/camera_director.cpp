// Per-frame camera of recorded runs; the modes are described in camera_director.h.
#include "render/camera_director.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "model/collider.h"

namespace clothsim::render {
namespace {

struct Box {
  Vec3 low;
  Vec3 high;
  bool empty = true;
};

Box bounding_box(std::span<const Vec3> position) {
  const double inf = std::numeric_limits<double>::infinity();
  Box box{{inf, inf, inf}, {-inf, -inf, -inf}, true};
  for (const Vec3& p : position) {
    if (!is_finite(p)) continue;
    box.empty = false;
    box.low = {std::min(box.low.x, p.x), std::min(box.low.y, p.y), std::min(box.low.z, p.z)};
    box.high = {std::max(box.high.x, p.x), std::max(box.high.y, p.y), std::max(box.high.z, p.z)};
  }
  return box;
}

void include(Box& box, const Vec3& low, const Vec3& high) {
  box.empty = false;
  box.low = {std::min(box.low.x, low.x), std::min(box.low.y, low.y), std::min(box.low.z, low.z)};
  box.high = {std::max(box.high.x, high.x), std::max(box.high.y, high.y), std::max(box.high.z, high.z)};
}

// Adds the bounds of every bounded collider where it is at `time`, so that the obstacle a sheet
// drapes over is in the picture. Planes are unbounded and left out: framing follows the sheet.
void include_colliders(Box& box, const ClothModel& model, double time) {
  for (const Collider& collider : model.colliders) {
    const Vec3 shift = collider.path.position(time) - collider.path.position(0.0);
    const Vec3 r{collider.radius, collider.radius, collider.radius};
    switch (collider.shape) {
      case ColliderShape::plane: break;
      case ColliderShape::sphere: include(box, collider.center + shift - r, collider.center + shift + r); break;
      case ColliderShape::box:
        include(box, collider.center + shift - collider.half_extents, collider.center + shift + collider.half_extents);
        break;
      case ColliderShape::capsule:
        for (const Vec3& end : {collider.a, collider.b}) include(box, end + shift - r, end + shift + r);
        break;
      case ColliderShape::mesh:
        if (collider.mesh == nullptr) break;
        for (const Vec3& vertex : collider.mesh->vertex) include(box, vertex + shift, vertex + shift);
        break;
    }
  }
}

std::array<Vec3, 8> corners(const Vec3& low, const Vec3& high) {
  return {Vec3{low.x, low.y, low.z},   Vec3{high.x, low.y, low.z},  Vec3{low.x, high.y, low.z},
          Vec3{high.x, high.y, low.z}, Vec3{low.x, low.y, high.z},  Vec3{high.x, low.y, high.z},
          Vec3{low.x, high.y, high.z}, Vec3{high.x, high.y, high.z}};
}

}  // namespace

CameraDirector::CameraDirector(const CameraChoice& choice, double aspect) : choice_(choice), aspect_(aspect) {
  camera_.azimuth = choice.azimuth;
  camera_.elevation = std::clamp(choice.elevation, -Camera::kMaxElevation, Camera::kMaxElevation);
}

void CameraDirector::update(const ClothModel& model, std::span<const Vec3> position, double time) {
  Box box = bounding_box(position);
  if (box.empty) return;  // nothing finite to look at: keep the last camera
  include_colliders(box, model, time);
  const bool first = !started_;
  if (first) {
    low_ = box.low;
    high_ = box.high;
    started_ = true;
  } else {
    low_ = {std::min(low_.x, box.low.x), std::min(low_.y, box.low.y), std::min(low_.z, box.low.z)};
    high_ = {std::max(high_.x, box.high.x), std::max(high_.y, box.high.y), std::max(high_.z, box.high.z)};
  }
  const double extent = std::max(high_.x - low_.x, high_.z - low_.z);
  ground_height_ = low_.y - std::max(0.05 * extent, model.spacing);

  switch (choice_.mode) {
    case CameraMode::automatic: {
      const std::array<Vec3, 8> seen = corners(low_, high_);
      camera_.fit(seen, aspect_);
      break;
    }
    case CameraMode::follow: {
      Camera goal = camera_;
      const std::array<Vec3, 8> now = corners(box.low, box.high);
      goal.fit(now, aspect_, 1.2);
      if (first) {
        camera_ = goal;
      } else {
        const double weight = 1.0 - std::exp(-std::max(time - last_time_, 0.0) / choice_.follow_time);
        camera_.target = camera_.target + weight * (goal.target - camera_.target);
        camera_.distance = camera_.distance + weight * (goal.distance - camera_.distance);
        // A low-pass lags behind a sheet that speeds up (by speed x follow_time): back off just
        // enough to keep this frame in view from the lagging target. Positions move
        // continuously, so the distance does too.
        camera_.distance = std::max(camera_.distance, camera_.fitting_distance(now, aspect_, 1.05));
      }
      break;
    }
    case CameraMode::fixed:
      if (first) {
        camera_.target = 0.5 * (box.low + box.high);
        camera_.distance = choice_.distance;
      }
      break;
  }
  last_time_ = time;
}

}  // namespace clothsim::render
