// The device step's shared layout (gpu/device_integrator.h and the shaders rk_*.comp,
// stage_acceleration.comp): the push constants of its passes and the slots of its two control
// arrays, read by C++ and by GLSL, so that the two cannot disagree on a layout or an index.
//
// The control arrays hold the step-size controller and the step's bookkeeping on the device, so
// that a step never waits for the host: `control_real` (Reals, the shader's precision) and
// `control_uint` (32-bit words). The host writes them before an advance and reads them back after
// each submission (DeviceIntegrator::advance); in between, only the shaders touch them.
#ifndef CLOTHSIM_DEVICE_STEP_H
#define CLOTHSIM_DEVICE_STEP_H
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
// 1 where the stage arrays hold offsets from the step's start rather than the stage state itself:
// float32 (stage_offsets.glsl says why).
#define CLOTHSIM_STAGE_OFFSETS (!CLOTHSIM_FLOAT64)
#endif

// control_real: times are relative to the advance's start (the host adds them to its double time).
CLOTHSIM_SLOT kStep = 0;           // s, the step the current attempt takes
CLOTHSIM_SLOT kTakenStep = 1;      // s, the step the last decision accepted
CLOTHSIM_SLOT kProposedStep = 2;   // s, the controller's proposal for the next step
CLOTHSIM_SLOT kPreviousError = 3;  // the PI controller's memory (explicit_runge_kutta.cpp)
CLOTHSIM_SLOT kElapsed = 4;        // s, simulated time since the advance began
CLOTHSIM_SLOT kTarget = 5;         // s, where the advance ends (t_limit - its start)
CLOTHSIM_SLOT kError = 6;          // the last attempt's scaled error norm
CLOTHSIM_SLOT kSmallestStep = 7;   // s, over this advance's accepted steps
CLOTHSIM_SLOT kLargestStep = 8;    // s
CLOTHSIM_SLOT kWork = 9;           // J, [12]: damping, drag, anchor, fracture, plastic and contact work of
                                   // this advance, each as a compensated sum (value, then its rounding error)
CLOTHSIM_SLOT kWorks = 6;
CLOTHSIM_SLOT kContactWork = 5;  // which of the works the obstacle pass books
CLOTHSIM_SLOT kMinStep = 21;     // the IntegratorSettings fields of the same names
CLOTHSIM_SLOT kMaxStep = 22;
CLOTHSIM_SLOT kSafety = 23;
CLOTHSIM_SLOT kMaxGrowth = 24;
CLOTHSIM_SLOT kMaxShrink = 25;
CLOTHSIM_SLOT kAbsoluteTolerance = 26;
CLOTHSIM_SLOT kRelativeTolerance = 27;
CLOTHSIM_SLOT kFixedStep = 28;   // s, the fixed-step methods' step (time_step)
CLOTHSIM_SLOT kHardening = 29;   // SpringLimits::hardening
CLOTHSIM_SLOT kStepStart = 30;   // s, where the last accepted step began
CLOTHSIM_SLOT kStepLimit = 31;   // s, the time the current attempt's step may not pass: the target, or
                                 // an impact ahead (kArrival); kClipped says the step ends on it
CLOTHSIM_SLOT kArrival = 32;     // s, the obstacles' limit (ObstacleContacts::begin_step); kNoArrival: none
CLOTHSIM_SLOT kThickness = 33;   // m, collision.thickness
CLOTHSIM_SLOT kControlReals = 34;
// No limit from the obstacles: far beyond any advance, and within float's range.
#define CLOTHSIM_NO_ARRIVAL 1e30

// control_uint.
CLOTHSIM_SLOT kActive = 0;          // 1 while the advance goes on: not at its target, not failed, not at max_accepted
CLOTHSIM_SLOT kClipped = 1;         // 1: the current attempt's step ends exactly at kStepLimit
CLOTHSIM_SLOT kAccepted = 2;        // 1: the last decision accepted its attempt (the accept pass reads it)
CLOTHSIM_SLOT kRejectedBefore = 3;  // 1: the step being sought was rejected once (no growth after it)
CLOTHSIM_SLOT kStatus = 4;          // a StepStatus: 0 ok, 1 step underflow, 2 non-finite
CLOTHSIM_SLOT kFailedParticle = 5;  // the particle named by a failure
CLOTHSIM_SLOT kNonFiniteError = 6;  // 1: the underflow came from non-finite stage values
CLOTHSIM_SLOT kAcceptedSteps = 7;   // in this advance
CLOTHSIM_SLOT kRejectedSteps = 8;   // in this advance
CLOTHSIM_SLOT kMaxAccepted = 9;     // the advance stops after this many accepted steps; 0: at its target
CLOTHSIM_SLOT kAdaptive = 10;       // 1: RKF45's error control; 0: a fixed step, checked for finiteness
CLOTHSIM_SLOT kAttempts = 11;       // attempts that ran in this advance
CLOTHSIM_SLOT kWorstParticle = 12;  // where the last attempt's error was largest
CLOTHSIM_SLOT kBreaks = 13;         // connectors broken in this advance (lattice_events)
CLOTHSIM_SLOT kYields = 14;         // connectors yielded
CLOTHSIM_SLOT kCreases = 15;        // radial springs creased
CLOTHSIM_SLOT kContacts = 16;       // particles the obstacle pass moved in the last accepted step
CLOTHSIM_SLOT kContactSteps = 17;   // the same, summed over this advance's steps
CLOTHSIM_SLOT kMostContacts = 18;   // the most in one step of this advance
CLOTHSIM_SLOT kControlUints = 19;

// The Nystrom rows of the method (explicit_runge_kutta.h) in the `rows` array, each kRowReals
// Reals: the sum of its weights, then sum_i w_i a_il for each stage l (positions), then w_l
// (velocities). Rows 0 .. stages-1 are the stages, then the solution (b), then the error (b - b^).
CLOTHSIM_SLOT kMaxDeviceStages = 6;
CLOTHSIM_SLOT kRowReals = 1 + 2 * kMaxDeviceStages;

// A path over an advance (an anchor's in `anchor_paths`, a collider's in `colliders`), kPathReals
// Reals, relative to the advance's start t0 (tau = t - t0): x(tau) = x0 + v tau + A (sin(theta0 +
// omega tau) - sin theta0), which covers every AnchorPath kind between path events
// (gpu/device_paths.h).
CLOTHSIM_SLOT kPathReals = 11;  // x0 (3), v (3), A (3), omega, theta0

// A collider on the device, kColliderReals Reals each in `colliders` (gpu/device_obstacles.cpp):
// its shape as given (model/collider.h, at t = 0), its Coulomb coefficient, and its path, whose x0
// is the shape's offset from where it is given (collider_offset()).
CLOTHSIM_SLOT kColliderShape = 0;     // kShapePlane ...
CLOTHSIM_SLOT kColliderFriction = 1;  // Coulomb coefficient
CLOTHSIM_SLOT kColliderFirst = 2;     // (3) plane: a point; sphere, box: the centre; capsule: a, m
CLOTHSIM_SLOT kColliderSecond = 5;    // (3) plane: the unit normal; box: the half extents; capsule: b
CLOTHSIM_SLOT kColliderRadius = 8;    // sphere, capsule: m
CLOTHSIM_SLOT kColliderPath = 9;      // kPathReals
CLOTHSIM_SLOT kColliderReals = 20;
CLOTHSIM_SLOT kShapePlane = 0;
CLOTHSIM_SLOT kShapeSphere = 1;
CLOTHSIM_SLOT kShapeBox = 2;
CLOTHSIM_SLOT kShapeCapsule = 3;
CLOTHSIM_SLOT kShapeMesh = 4;
// The triangle meshes of mesh colliders, in `mesh_uints` and `mesh_reals` (gpu/device_obstacles.cpp):
// first kMeshHeaderUints words per collider (zeros for the other shapes): where its Reals and its
// words start, its vertex, triangle and hierarchy node counts. A mesh's Reals are its vertices (3 V),
// vertex pseudonormals (3 V), triangle normals (3 T), edge pseudonormals (9 T), nodes' low and high
// corners (3 N each); its words its triangles' corners (3 T), nodes' first child, first triangle
// and triangle count (N each) and the triangles in leaf order (T): TriangleMesh's arrays
// (model/collider.h).
CLOTHSIM_SLOT kMeshHeaderUints = 5;
// The obstacle passes' partial results per workgroup, in `block_obstacles`.
CLOTHSIM_SLOT kObstacleBlockReals = 3;  // contact work (J), particles moved, the earliest arrival (s)

// The lattice path (lattice_elements.comp): per particle, kLatticeParams Reals in
// `lattice_params`, its east and south connectors (d 0, 1) and its six radial springs (pair k in
// model/lattice_springs.inc's order), each spring's four parameters at the offsets below; its
// springs' force on itself (3) and on its four neighbours (4 x 3) in `lattice_forces`.
CLOTHSIM_SLOT kLatticeParams = 32;
CLOTHSIM_SLOT kLatticeForces = 15;
// lattice_stage's tile: kStageTile x kStageTile particles a workgroup, one an invocation.
CLOTHSIM_SLOT kStageTile = 8;
// The most stages lattice_stage chains in one pass, by precision: its shared arrays, sized for
// them, stay within the 32 kB every device offers (docs/gpu.md, "Stages chained in a pass").
CLOTHSIM_SLOT kMaxChainedStagesFloat32 = 3;
CLOTHSIM_SLOT kMaxChainedStagesFloat64 = 1;
CLOTHSIM_SLOT kSpringParams = 4;       // Reals per spring
CLOTHSIM_SLOT kConnectorParams = 0;    // connector d at kConnectorParams + kSpringParams * d
CLOTHSIM_SLOT kRadialParams = 8;       // radial spring k at kRadialParams + kSpringParams * k
CLOTHSIM_SLOT kParamRest = 0;          // m, the rest length; rad, the rest angle
CLOTHSIM_SLOT kParamStiffness = 1;     // N/m; N m/rad
CLOTHSIM_SLOT kParamDamping = 2;       // the damping coefficient
CLOTHSIM_SLOT kParamActive = 3;        // 1: live and its force term on; 0: absent, broken or off
// The laws of events/spring_laws.inc on the lattice path, per particle, kEventParams Reals in
// `event_params`: the east and south connectors' four values at kEventsPerConnector * d, then the
// six radial springs' yield angles at kRadialYieldAngles + k.
CLOTHSIM_SLOT kEventParams = 16;
CLOTHSIM_SLOT kEventsPerConnector = 4;
CLOTHSIM_SLOT kEventOriginalLength = 0;  // m
CLOTHSIM_SLOT kEventBreakStrain = 1;     // +inf: never breaks
CLOTHSIM_SLOT kEventYieldStrain = 2;     // +inf: never yields; grows with hardening
CLOTHSIM_SLOT kEventBreakTime = 3;       // s, elapsed in the advance when it broke
CLOTHSIM_SLOT kRadialYieldAngles = 8;    // rad, +inf: never creases

// The event passes' `laws` bits.
CLOTHSIM_SLOT kLawTearing = 1;
CLOTHSIM_SLOT kLawPlasticity = 2;  // permanent stretching
CLOTHSIM_SLOT kLawCreasing = 4;

// The passes' push constants.
struct StagePassConstants {
  uint particle_count;
  uint stage;         // which row of `rows` and which acceleration array
  uint stages;        // the method's stage count
  uint symplectic;    // rk_solution: 1 for symplectic Euler's update instead of the row b
  uint lattice_cols;  // stage_acceleration: the lattice's columns on the lattice path; 0: the general path
};

// LatticePassConstants::params_particle where each particle reads its own springs' parameters.
CLOTHSIM_SLOT kOwnParams = 0xffffffffu;

struct LatticePassConstants {
  uint particle_count;
  uint rows;
  uint cols;
  uint damped;  // 1: the springs' damping acts (kSpringDamping)
  uint stage;   // the stage whose damping power is weighed into particle_power (lattice_stage: its first)
  uint stages;  // the method's stages (where its solution row is in `rows`)
  // kOwnParams, or on a uniform sheet (every spring of a kind the same, and no law that changes
  // them) the interior particle whose parameters and arm lengths every particle reads: one
  // particle's 32 reals, in the cache for all, instead of each particle's own.
  uint params_particle;
  // lattice_stage's pass that ends the attempt forms the trial state as well: 1 for symplectic
  // Euler's update instead of the row b (StagePassConstants::symplectic).
  uint symplectic;
  uint pass_stages;  // lattice_stage: the stages it chains, from `stage` on
};

struct EventPassConstants {
  uint particle_count;
  uint rows;
  uint cols;
  uint laws;    // kLawTearing | kLawPlasticity | kLawCreasing: the laws that act
  uint blocks;  // lattice_events_radial: its workgroups
};

struct ReducePassConstants {
  uint count;   // items reduced (particles, or elements)
  uint blocks;  // workgroups of the pass whose partial results are reduced
  // rk_control: 0 decides on the attempt, 1 adds the accepted step's work, 2 the events' work, 3
  // adds the last accepted step's work of a submission (phase 1's) and marks it added
  uint phase;
  uint stages;
  uint obstacles;  // 1: the obstacle passes run; phase 1 adds their work and sets the next step
  // Phase 0 without obstacles: rk_accept's workgroups, whose work for the step accepted before
  // this attempt the decision adds first (phase 1's work, without a dispatch of its own); 0: none.
  uint work_blocks;
};

struct ObstaclePassConstants {
  uint particle_count;
  uint rows;  // the lattice (obstacle_energy walks each particle's springs)
  uint cols;
  uint colliders;
  // obstacle_contacts: 1 where the integrator held particles on their surfaces during the step
  // (implicit Euler): friction acts on the normal impulse the surface exerted (model/surface_contacts.h).
  uint holds;
};

// obstacle_energy_elements (implicit Euler's obstacle pass, on DeviceForces' element arrays): its
// phases, one dispatch each, writing their workgroups' kObstacleBlockReals at first_block on.
CLOTHSIM_SLOT kObstacleParticlesPhase = 0;   // the moved particles' energy, the surface impulses' work,
                                             // the particles moved, the earliest arrival, the surface contacts
CLOTHSIM_SLOT kObstacleConnectorsPhase = 1;  // the connectors touching a moved particle: their energy change
CLOTHSIM_SLOT kObstacleRadialsPhase = 2;     // the radial springs likewise

struct ObstacleElementConstants {
  uint count;        // items of the phase: particles, connectors or radial springs
  uint phase;        // kObstacle*Phase
  uint first_block;  // where the phase's workgroups write in block_obstacles
  uint colliders;
  uint start;  // 1: at an advance's start, nothing moved: the surface contacts and the arrival only
};

struct AcceptPassConstants {
  uint particle_count;
  uint element_count;  // connectors + radial springs
  uint stages;
  uint blocks;            // the pass's workgroups: ceil(max(particles, elements) / kReduceWorkgroup)
  uint particle_damping;  // 1: the damping power is per particle (the lattice path; element_count 0)
};

// The workgroup size of the passes that reduce in shared memory (rk_solution, rk_accept,
// rk_control): fixed, because their shared arrays are.
CLOTHSIM_SLOT kReduceWorkgroup = 256;

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
#if !defined(__cplusplus)
// Where the solution row's velocity weight b_stage of a method of `stages` stages is in `rows` (the
// Nystrom rows: the stages' rows, then the solution's, then the error's). particle_power holds
// each particle's powers weighed by these and summed over the stages so far, [3][particles]: drag,
// anchor, damping (stage_acceleration and lattice_elements add, rk_accept multiplies by h).
uint solution_weight_slot(uint stages, uint stage) { return stages * kRowReals + 1u + kMaxDeviceStages + stage; }
#endif
#endif  // CLOTHSIM_DEVICE_STEP_H
