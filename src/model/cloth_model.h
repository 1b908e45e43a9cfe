// The three kinds of simulation data (after MuJoCo's mjModel/mjData split):
//
//   ClothModel  topology and per-element parameters. Built once by build_lattice() and then only
//               read: integrators take `const ClothModel&`. Events that change the sheet
//               (tearing, plasticity, creasing) will rewrite it between steps, never inside one.
//   ClothState  what evolves: time, positions, velocities and the work integrals. Cheap to copy.
//   Workspace   scratch memory owned by an integrator (integrators/).
//
// Every array is a structure-of-arrays member named entity_attribute; the comment on each states
// the count it is indexed by and its unit. Elements refer to particles by 32-bit index.
//
// Units are SI throughout. Radial (angular) spring stiffness is a torque per radian (N m / rad),
// damping a torque per angular velocity (N m s / rad); angles are radians. The paper multiplies
// degree differences by pi/180, which is the same thing (docs/model.md).
#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "model/anchor.h"

namespace clothsim {

// A radial spring joins two connector springs that meet at a particle: two adjacent connectors
// (rest angle 90 degrees on a square lattice) or two opposite ones (rest angle 180 degrees).
enum class RadialKind : std::uint8_t { adjacent, opposite };

// The three spring families of the paper, each with one (k, c) pair in its argument vector.
enum class SpringFamily : std::uint8_t { connector, adjacent, opposite };

struct SpringParameters {
  double stiffness = 0.0;  // connector: N/m; radial: N m / rad
  double damping = 0.0;    // connector: N s/m; radial: N m s / rad
};

// Everything that defines a uniform rectangular sheet. The paper's 10-number argument vector maps
// onto it field by field (scene/paper_args.h).
struct LatticeDef {
  int rows = 21;                // particles along z (the paper's "vertical points")
  int cols = 21;                // particles along x (the paper's "horizontal points")
  double spacing = 1.0;         // connector rest length L, m
  double particle_mass = 1.0;   // kg, the same for every particle
  SpringParameters connector{80.0, 5.0};
  SpringParameters adjacent{4.0, 1.0};
  double adjacent_rest_angle = std::numbers::pi / 2.0;  // rad
  SpringParameters opposite{1400.0, 200.0};
  double opposite_rest_angle = std::numbers::pi;  // rad
};

// Forces from outside the sheet.
struct Environment {
  Vec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  double air_drag = 0.0;          // linear drag coefficient per particle, kg/s: f = -air_drag v
};

struct ClothModel {
  // Lattice shape, for output and rendering; the physics uses only the element arrays below.
  int rows = 0;
  int cols = 0;
  double spacing = 0.0;  // m

  // Particles [particle_count()].
  std::vector<double> particle_mass;          // kg
  std::vector<double> particle_inverse_mass;  // 1/kg; 0 for anchored particles
  std::vector<std::int32_t> particle_anchor;  // index into `anchors`, or -1 for a free particle
  std::vector<Vec3> particle_rest_position;   // flat lattice position, m

  // Connector springs [connector_count()]: f_a = (k (l - L) + c (v_b - v_a).u) u, f_b = -f_a.
  std::vector<std::array<std::uint32_t, 2>> connector_particles;  // (a, b)
  std::vector<double> connector_rest_length;  // L, m
  std::vector<double> connector_stiffness;    // k, N/m
  std::vector<double> connector_damping;      // c, N s/m

  // Radial springs [radial_count()]: energy 1/2 k (theta - theta0)^2 of the angle theta between
  // the connectors centre->b and centre->c, plus damping -c dtheta/dt along the same gradient.
  std::vector<std::array<std::uint32_t, 3>> radial_particles;   // (centre, b, c)
  std::vector<std::array<std::uint32_t, 2>> radial_connectors;  // (centre-b, centre-c) connector indices
  std::vector<RadialKind> radial_kind;
  std::vector<double> radial_rest_angle;  // theta0, rad, in [0, pi]
  std::vector<double> radial_stiffness;   // k, N m / rad
  std::vector<double> radial_damping;     // c, N m s / rad

  // Anchors [anchor_count()].
  std::vector<Anchor> anchors;

  Environment environment;

  // Force gather table (CSR). Element forces are written to per-element slots, then each
  // particle sums its slots in ascending order; this is what makes results independent of the
  // thread count. Connector e owns slots 2e (a) and 2e+1 (b); radial spring r owns slots
  // radial_slot_base() + 3r (centre), +1 (b), +2 (c).
  std::vector<std::uint32_t> gather_offset;  // [particle_count() + 1]
  std::vector<std::uint32_t> gather_slot;    // [gather_offset.back()]

  std::size_t particle_count() const { return particle_mass.size(); }
  std::size_t connector_count() const { return connector_particles.size(); }
  std::size_t radial_count() const { return radial_particles.size(); }
  std::size_t anchor_count() const { return anchors.size(); }
  std::size_t radial_slot_base() const { return 2 * connector_count(); }
  std::size_t force_slot_count() const { return 2 * connector_count() + 3 * radial_count(); }

  bool is_anchored(std::size_t particle) const { return particle_anchor[particle] >= 0; }
  // "particle 37 (row 1, col 16)" for diagnostics.
  std::string describe_particle(std::size_t particle) const;
};

struct ClothState {
  double time = 0.0;            // s
  std::vector<Vec3> position;   // [particle_count()], m
  std::vector<Vec3> velocity;   // [particle_count()], m/s
  // Work done on the sheet since t = 0, integrated alongside the motion so that the energy
  // balance E(t) = E(0) + W_damping + W_drag + W_anchor can be checked at any time.
  double damping_work = 0.0;  // by spring damping, J (never positive)
  double drag_work = 0.0;     // by air drag, J (never positive)
  double anchor_work = 0.0;   // by moving anchors, J
};

// Builds the lattice of the paper: particle (i, j) has index i*cols + j and rest position
// ((j - (cols-1)/2) L, 0, (i - (rows-1)/2) L). Anchors name particles by index; a particle may be
// anchored once. Throws InputError naming `source` for inconsistent definitions.
ClothModel build_lattice(const LatticeDef& lattice, const Environment& environment,
                         std::span<const Anchor> anchors, const std::string& source = "lattice");

// The flat lattice at rest, anchors at their path positions at time 0.
ClothState make_rest_state(const ClothModel& model);

// Edits of a built model, for live editing between steps (Simulation wraps them so that the
// integrator and the energy balance stay consistent; call these directly only on a model no
// integrator is using). Each keeps the model's invariants: inverse masses match masses and
// anchors, particle_anchor indexes `anchors`.
//
// Sets the stiffness and damping of every spring of `family` (a per-spring variation is replaced).
void set_spring_family(ClothModel& model, SpringFamily family, const SpringParameters& parameters);
// Sets every particle's mass, kg (> 0); anchored particles keep inverse mass 0.
void set_particle_mass(ClothModel& model, double mass);
// Anchors `particle` to `path`, replacing the path if it is anchored already.
void set_anchor(ClothModel& model, std::uint32_t particle, const AnchorPath& path);
// Frees an anchored particle (its inverse mass is restored from its mass); false if it was free.
// The last anchor takes the freed one's index in `anchors`.
bool remove_anchor(ClothModel& model, std::uint32_t particle);

// Index of particle (row, col).
inline std::uint32_t lattice_index(int cols, int row, int col) {
  return static_cast<std::uint32_t>(row * cols + col);
}

}  // namespace clothsim
