// The three kinds of simulation data (after MuJoCo's mjModel/mjData split):
//
//   ClothModel  topology and per-element parameters. Built once by build_lattice(); afterwards
//               changed only through model/model_edits.h (tearing, plasticity, creasing, live
//               edits), between steps and never inside one, each change counted in `revision`.
//               Integrators take `const ClothModel&` and refresh what they cache from it when
//               the revision moves.
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
#include "model/collider.h"
#include "model/spring_limits.h"

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
  int rows = 21;               // particles along z (the paper's "vertical points")
  int cols = 21;               // particles along x (the paper's "horizontal points")
  double spacing = 1.0;        // connector rest length L, m
  double particle_mass = 1.0;  // kg, the same for every particle
  SpringParameters connector{80.0, 5.0};
  SpringParameters adjacent{4.0, 1.0};
  double adjacent_rest_angle = std::numbers::pi / 2.0;  // rad
  SpringParameters opposite{1400.0, 200.0};
  double opposite_rest_angle = std::numbers::pi;  // rad
  // Tearing, permanent stretching and creasing (model/spring_limits.h); +inf: never, the paper's
  // sheet. build_lattice() leaves every spring unlimited; scene/ applies these to the built model
  // with the scene's seed as variation_seed.
  SpringLimits limits{};
};

// Forces from outside the sheet.
struct Environment {
  Vec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  double air_drag = 0.0;          // linear drag coefficient per particle, kg/s: f = -air_drag v
};

// How the element arrays are ordered. build_lattice() records `lattice`: connectors and radial
// springs in its order (see there), which the structured force kernel (forces/lattice_kernel.h)
// relies on instead of finding neighbours through the element lists. Anything else is `general`.
// The layout never changes: a broken spring stays in its place, marked dead.
enum class ModelLayout : std::uint8_t { general, lattice };

struct ClothModel {
  // Lattice shape, for output and rendering; the physics uses only the element arrays below.
  int rows = 0;
  int cols = 0;
  double spacing = 0.0;  // m
  ModelLayout layout = ModelLayout::general;
  // Counts every change made through model/model_edits.h since the model was built. A cache
  // derived from the model (the lattice kernel's per-spring arrays, implicit Euler's matrix
  // values, a derivative kept between steps) records the revision it was made for and refreshes
  // itself when it differs; nothing has to be rebuilt, and integrators keep their state.
  std::uint64_t revision = 0;

  // Particles [particle_count()].
  std::vector<double> particle_mass;          // kg
  std::vector<double> particle_inverse_mass;  // 1/kg; 0 for anchored particles
  std::vector<std::int32_t> particle_anchor;  // index into `anchors`, or -1 for a free particle
  std::vector<Vec3> particle_rest_position;   // flat lattice position, m

  // Connector springs [connector_count()]: f_a = (k (l - L) + c (v_b - v_a).u) u, f_b = -f_a.
  std::vector<std::array<std::uint32_t, 2>> connector_particles;  // (a, b)
  std::vector<double> connector_rest_length;                      // L, m
  std::vector<double> connector_stiffness;                        // k, N/m
  std::vector<double> connector_damping;                          // c, N s/m
  // Changing parts of a connector (DESIGN.md section 3, events/): whether it is intact, the
  // strain at which it breaks, and the yield strain of its plastic law. A broken connector and
  // every radial spring using it exert no force and store no energy; they keep their index.
  std::vector<std::uint8_t> connector_live;       // 1 intact, 0 broken
  std::vector<double> connector_break_time;       // simulated time it broke, s; +inf while intact
  std::vector<double> connector_original_length;  // L as built, m: strains of tearing and plasticity
  std::vector<double> connector_break_strain;     // breaks when l / original - 1 > this; +inf: never
  std::vector<double> connector_yield_strain;     // y_e of the return mapping; grows by hardening; +inf: elastic

  // Radial springs [radial_count()]: energy 1/2 k (theta - theta0)^2 of the angle theta between
  // the connectors centre->b and centre->c, plus damping -c dtheta/dt along the same gradient.
  std::vector<std::array<std::uint32_t, 3>> radial_particles;   // (centre, b, c)
  std::vector<std::array<std::uint32_t, 2>> radial_connectors;  // (centre-b, centre-c) connector indices
  std::vector<RadialKind> radial_kind;
  std::vector<double> radial_rest_angle;      // theta0, rad, in [0, pi]
  std::vector<double> radial_stiffness;       // k, N m / rad
  std::vector<double> radial_damping;         // c, N m s / rad
  std::vector<std::uint8_t> radial_live;      // 0 once one of its connectors broke
  std::vector<double> radial_original_angle;  // theta0 as built, rad
  std::vector<double> radial_yield_angle;     // creasing: largest |theta - theta0| kept elastic, rad; +inf: elastic

  // Radial springs using each connector (CSR): radial_of_connector[connector_radial_offset[e] ..
  // connector_radial_offset[e + 1]), ascending. Breaking e kills exactly these.
  std::vector<std::uint32_t> connector_radial_offset;  // [connector_count() + 1]
  std::vector<std::uint32_t> radial_of_connector;

  // The limits the per-spring thresholds above were set from (model/spring_limits.h); the
  // hardening of the plastic law is read from here.
  SpringLimits limits;

  // Anchors [anchor_count()].
  std::vector<Anchor> anchors;

  Environment environment;

  // Obstacles and collision settings (model/collider.h; collision/ responds to them).
  std::vector<Collider> colliders;
  CollisionSettings collision;

  // Element force slots of the general force path (model/gather_table.h): connector e owns slots
  // 2e (a) and 2e+1 (b); radial spring r owns slots radial_slot_base() + 3r (centre), +1 (b), +2 (c).

  std::size_t particle_count() const { return particle_mass.size(); }
  std::size_t connector_count() const { return connector_particles.size(); }
  std::size_t radial_count() const { return radial_particles.size(); }
  std::size_t anchor_count() const { return anchors.size(); }
  std::size_t radial_slot_base() const { return 2 * connector_count(); }
  std::size_t force_slot_count() const { return 2 * connector_count() + 3 * radial_count(); }

  bool is_anchored(std::size_t particle) const { return particle_anchor[particle] >= 0; }
  // Bytes held by the arrays (capacity, not just size); the obstacles are not counted (a mesh is
  // shared with the scene, and the rest is a few hundred bytes each).
  std::size_t bytes() const;
  bool is_intact() const { return broken_connector_count == 0; }
  // Connectors broken so far (kept by model_edits.h).
  std::size_t broken_connector_count = 0;
  // "particle 37 (row 1, col 16)" for diagnostics.
  std::string describe_particle(std::size_t particle) const;
};

struct ClothState {
  double time = 0.0;           // s
  std::vector<Vec3> position;  // [particle_count()], m
  std::vector<Vec3> velocity;  // [particle_count()], m/s
  // Work done on the sheet since t = 0, integrated alongside the motion so that the energy
  // balance E(t) = E(0) + W_damping + W_drag + W_anchor + W_plastic + W_fracture + W_contact can be
  // checked.
  double damping_work = 0.0;  // by spring damping, J (never positive)
  double drag_work = 0.0;     // by air drag, J (never positive)
  double anchor_work = 0.0;   // by moving anchors, J
  // Elastic energy released between steps by the events of events/ (and cuts), J (never
  // positive): yielding and creasing, and breaking springs.
  double plastic_work = 0.0;
  double fracture_work = 0.0;
  // Energy the collision stage (collision/) changed between steps by moving particles out of
  // obstacles and correcting their velocities, J. Never positive against static obstacles; a
  // moving obstacle that pushes the sheet does positive work.
  double contact_work = 0.0;
};

// The element counts of the rows x cols lattice that build_lattice() makes: what a scene needs can
// be known before it is built (the memory estimate, sim/memory_estimate.h).
struct LatticeCounts {
  std::size_t rows = 0;
  std::size_t cols = 0;
  std::size_t particles = 0;   // rows cols
  std::size_t connectors = 0;  // rows (cols - 1) + (rows - 1) cols
  std::size_t radials = 0;     // 4 (rows - 1)(cols - 1) adjacent + rows (cols - 2) + cols (rows - 2) opposite
};
LatticeCounts lattice_counts(std::size_t rows, std::size_t cols);

// The bytes ClothModel::bytes() reports for the model build_lattice() makes with `counts` and
// `anchors` anchors, before it is built.
std::size_t lattice_model_bytes(const LatticeCounts& counts, std::size_t anchors);

// Builds the lattice of the paper: particle (i, j) has index i*cols + j and rest position
// ((j - (cols-1)/2) L, 0, (i - (rows-1)/2) L). Anchors name particles by index; a particle may be
// anchored once. Throws InputError naming `source` for inconsistent definitions. Every spring is
// intact, unbreakable and elastic (limits +inf); scene/ sets the limits of a material.
ClothModel build_lattice(const LatticeDef& lattice, const Environment& environment, std::span<const Anchor> anchors,
                         const std::string& source = "lattice");

// The flat lattice at rest, anchors at their path positions at time 0.
ClothState make_rest_state(const ClothModel& model);

// Completes a model whose element arrays are filled in: the per-spring state of tearing and
// plasticity (intact, limits +inf, original rest values) where it is missing, and the
// connector-to-radial table. build_lattice() calls it; so does code that builds a
// model by hand (tests of irregular sheets).
void finish_model(ClothModel& model);

// Pieces of the sheet: connected components of its particles over intact connectors (an
// intact sheet is 1 piece; a torn one falls apart into more).
std::size_t count_pieces(const ClothModel& model);

// Index of particle (row, col).
inline std::uint32_t lattice_index(int cols, int row, int col) { return static_cast<std::uint32_t>(row * cols + col); }

}  // namespace clothsim
