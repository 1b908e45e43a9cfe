// The anchor stage between steps: what happens to anchors at an instant rather than along a step.
//
// A step never crosses an anchor event (next_anchor_event bounds it), so each of these happens
// exactly at the end of a step, in this order (apply_anchor_events):
//   1. a driven anchor that has arrived stops: it is held where its path ends, and the jump of its
//      particle's velocity to rest is the anchor's impulse;
//   2. a keyframed path's key: the particle takes the next segment's velocity, again an impulse;
//   3. an anchor whose release time has come lets go: the particle goes on with the velocity it
//      has, so no energy changes.
// An impulse's work, 1/2 m (|v_after|^2 - |v_before|^2), goes into ClothState::anchor_work like
// the anchor's continuous work along its path, so the energy balance stays exact. Every change
// goes through model/model_edits.h.
#pragma once

#include <cstdint>

#include "model/anchor.h"
#include "model/cloth_model.h"

namespace clothsim {

// The next anchor event after `time` (a moving driven anchor arriving, a keyframe, an anchor's
// release time), s, or +infinity.
double next_anchor_event(const ClothModel& model, double time);
// The next event of a path after `time`, s, or +infinity: a moving driven path's arrival, a
// keyframed path's key (its velocity jumps at both).
double next_path_event(const AnchorPath& path, double time);
// The next event of a collider's path after `time`, s, or +infinity. The CPU's collision stage
// evaluates a path at any time and needs none; the device writes each collider's path per advance
// as one segment (gpu/device_paths.h), so its advances stop at them.
double next_collider_event(const ClothModel& model, double time);

// The events due at state.time, in the order above.
void apply_anchor_events(ClothModel& model, ClothState& state);

// Puts `particle` on `path` (anchoring it if it was free) and its velocity to the path's, booking
// the velocity's jump as anchor work: a driven anchor stopping, a pin or drive of the viewer.
void hold_on_path(ClothModel& model, ClothState& state, std::uint32_t particle, const AnchorPath& path);

}  // namespace clothsim
