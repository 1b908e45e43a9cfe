#include "sim/anchor_events.h"

#include <algorithm>
#include <limits>

#include "model/model_edits.h"

namespace clothsim {
namespace {

// A driven anchor that has arrived stops where its path ends.
void stop_arrived_anchors(ClothModel& model, ClothState& state) {
  for (const Anchor& anchor : model.anchors) {
    const AnchorPath& path = anchor.path;
    if (path.kind != AnchorPathKind::driven || path.velocity == Vec3{} || path.end_time > state.time) continue;
    AnchorPath held;
    held.kind = AnchorPathKind::driven;
    held.origin = path.position(path.end_time);
    held.start_time = path.end_time;
    // hold_on_path() only rewrites this anchor's path, so the loop's iteration stays valid.
    hold_on_path(model, state, anchor.particle, held);
  }
}

// A keyframed anchor at a key: the step that ended here left the particle on the new segment's
// velocity (its path's velocity at this time); the jump is the anchor's impulse.
void book_anchor_keys(const ClothModel& model, ClothState& state) {
  for (const Anchor& anchor : model.anchors) {
    const Vec3 before = anchor.path.velocity_before(state.time);
    const Vec3 after = anchor.path.velocity_at(state.time);
    if (before == after) continue;
    state.anchor_work += 0.5 * model.particle_mass[anchor.particle] * (squared_norm(after) - squared_norm(before));
  }
}

void release_due_anchors(ClothModel& model, double time) {
  // remove_anchor() moves the last anchor into the freed slot, so scan from the back.
  for (std::size_t i = model.anchors.size(); i-- > 0;) {
    if (i < model.anchors.size() && model.anchors[i].release_time <= time) {
      remove_anchor(model, model.anchors[i].particle);
    }
  }
}

}  // namespace

double next_path_event(const AnchorPath& path, double time) {
  double next = std::numeric_limits<double>::infinity();
  if (path.kind == AnchorPathKind::driven && path.velocity != Vec3{} && path.end_time > time) next = path.end_time;
  // A keyframed path's keys are velocity discontinuities (+inf for other kinds).
  return std::min(next, path.next_key_after(time));
}

double next_anchor_event(const ClothModel& model, double time) {
  double next = std::numeric_limits<double>::infinity();
  for (const Anchor& anchor : model.anchors) {
    next = std::min(next, next_path_event(anchor.path, time));
    if (anchor.release_time > time) next = std::min(next, anchor.release_time);
  }
  return next;
}

double next_collider_event(const ClothModel& model, double time) {
  double next = std::numeric_limits<double>::infinity();
  for (const Collider& collider : model.colliders) next = std::min(next, next_path_event(collider.path, time));
  return next;
}

void apply_anchor_events(ClothModel& model, ClothState& state) {
  stop_arrived_anchors(model, state);
  book_anchor_keys(model, state);
  release_due_anchors(model, state.time);
}

void hold_on_path(ClothModel& model, ClothState& state, std::uint32_t particle, const AnchorPath& path) {
  const Vec3 before = state.velocity[particle];
  set_anchor(model, particle, path);
  state.position[particle] = path.position(state.time);
  state.velocity[particle] = path.velocity_at(state.time);
  state.anchor_work +=
      0.5 * model.particle_mass[particle] * (squared_norm(state.velocity[particle]) - squared_norm(before));
}

}  // namespace clothsim
