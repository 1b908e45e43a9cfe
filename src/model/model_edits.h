// The one seam through which a built model changes (STYLE.md rule 2: the model is otherwise
// read-only).
//
// Every change to a ClothModel after build_lattice() goes through a function here: the events of
// tearing, plasticity and creasing (events/), the viewer's live edits and cuts (through
// Simulation), anchors that are set, driven and released, obstacles added and moved by hand and
// self-collision switched on or off. Each increments ClothModel::revision.
// Whatever is derived from the model and kept between force evaluations compares that revision
// and refreshes itself in place:
//   - the lattice kernel's per-spring arrays (forces/lattice_kernel.h),
//   - implicit Euler's matrix values (its block pattern never changes: see below),
//   - a derivative an integrator kept from its last step.
// So an integrator survives a change with its step-size history and warm starts intact; nothing
// is rebuilt.
//
// Why tearing marks springs dead instead of removing them: element indices, the force gather
// table, implicit Euler's block pattern, the lattice kernel's layout, the output's connector
// numbering and the GPU's buffers all stay valid, and a broken spring is one byte in a mask. The
// cost is a few dead springs still visited by the loops, which is what a vectorised loop wants
// anyway. Particles are never split: the physics of a torn lattice needs none (a particle keeps
// all the springs it still has), and splitting would renumber the state. The rendered mesh splits
// its vertices instead (model/sheet_mesh.h).
//
// These functions change the model only; booking the energy a change releases (plastic and
// fracture work) is the caller's job (events/, sim/), which knows the state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "model/anchor.h"
#include "model/cloth_model.h"
#include "model/collider.h"

namespace clothsim {

// Breaks connector `connector` and every radial spring that uses it, recording `time` (s) as
// its break time. Returns false (and changes nothing) if it was broken already.
bool break_connector(ClothModel& model, std::uint32_t connector, double time = 0.0);

// Rest length of a connector, m (> 0).
void set_connector_rest_length(ClothModel& model, std::uint32_t connector, double rest_length);
// Current yield strain of a connector (> 0, +inf: elastic).
void set_connector_yield_strain(ClothModel& model, std::uint32_t connector, double yield_strain);
// Rest angle of a radial spring, rad, in [0, pi].
void set_radial_rest_angle(ClothModel& model, std::uint32_t radial, double rest_angle);

// Live edits of the whole sheet.
//
// Sets the stiffness and damping of every spring of `family` (a per-spring variation is replaced).
void set_spring_family(ClothModel& model, SpringFamily family, const SpringParameters& parameters);
// Sets every particle's mass, kg (> 0); anchored particles keep inverse mass 0.
void set_particle_mass(ClothModel& model, double mass);
// Gravity and air drag.
void set_environment(ClothModel& model, const Environment& environment);
// Anchors `particle` to `path`, replacing the path if it is anchored already.
void set_anchor(ClothModel& model, std::uint32_t particle, const AnchorPath& path);
// Frees an anchored particle (its inverse mass is restored from its mass); false if it was free.
// The last anchor takes the freed one's index in `anchors`.
bool remove_anchor(ClothModel& model, std::uint32_t particle);

// Obstacles and collision settings, live (the viewer's hand on a sphere, its self-collision switch).
//
// Self-collision on or off (collision.self); the collision stage reads it every step.
void set_self_collision(ClothModel& model, bool on);
// Appends an obstacle; returns its index in model.colliders.
std::size_t add_collider(ClothModel& model, const Collider& collider);
// Moves collider `collider` rigidly, in a straight line at constant velocity, by `displacement`
// (m) from where it is at `now` (s), arriving at `arrival_time` (> now), and holds it there after.
// The motion is the collider's path (a driven path, model/anchor.h), not a jump of its shape:
// the collision stage sweeps particles in the collider's frame over each step and takes the
// surface velocity from the path, so a collider moved this way pushes the sheet ahead of it, and
// one that jumped would pass through particles without touching them. A scene path the collider
// had is replaced. Not for meshes (their vertices are shared and never change).
void drive_collider(ClothModel& model, std::size_t collider, const Vec3& displacement, double now, double arrival_time);
// Moves collider `collider` by `displacement` at once, and holds it there (a drag while paused,
// when no time passes): particles it now overlaps are pushed out through its nearest surface at
// the next step. Not for meshes.
void place_collider(ClothModel& model, std::size_t collider, const Vec3& displacement, double now);

}  // namespace clothsim
