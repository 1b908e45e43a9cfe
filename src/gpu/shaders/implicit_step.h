// The layout shared by implicit Euler on the device (gpu/device_implicit_euler.h) and its shaders
// implicit_*.comp: the slots of its two solve arrays, the element factors' widths and the push
// constants, read by C++ and by GLSL, so that the two cannot disagree on a layout or an index.
//
// The solve arrays are host-visible: the host writes a step's scalars into `solve_real` before
// the step and reads the conjugate gradients' progress from `solve_uint` between submissions,
// without copies; in between, only the shaders touch them.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

// solve_real (Reals, the shaders' precision). The host writes the first four per step.
CLOTHSIM_SLOT kImplicitStep = 0;         // s, h
CLOTHSIM_SLOT kStiffnessScale = 1;       // h^2: K's factor in A = M + h (C + drag) + h^2 K
CLOTHSIM_SLOT kDampingScale = 2;         // h
CLOTHSIM_SLOT kRelativeResidual = 3;     // cg_tolerance: CG stops at |r| <= this |b|
CLOTHSIM_SLOT kRho = 4;                  // r . z of the current iterate
CLOTHSIM_SLOT kAlpha = 5;                // the step along the direction
CLOTHSIM_SLOT kBeta = 6;                 // the next direction's share of the last
CLOTHSIM_SLOT kTargetResidual = 7;       // (cg_tolerance |b|)^2
CLOTHSIM_SLOT kResidualNorm2 = 8;        // |r|^2 of the current iterate
CLOTHSIM_SLOT kDampingPower = 9;         // W, at the step's end: the springs' damping
CLOTHSIM_SLOT kDragPower = 10;           // W: air drag
CLOTHSIM_SLOT kAnchorPower = 11;         // W: what the anchors do to keep their particles on the paths
// The obstacle pass after the step (gpu/device_implicit_obstacles.cpp), or at an advance's start:
CLOTHSIM_SLOT kObstacleWork = 12;     // J: the energy it changed and the held particles' surface impulses' work
CLOTHSIM_SLOT kObstacleMoved = 13;    // the particles it moved
CLOTHSIM_SLOT kObstacleArrival = 14;  // s from the state's time: the next step ends by it (none: CLOTHSIM_NO_ARRIVAL)
// The spring laws after the step and its obstacle pass (implicit_events.comp): the host writes the
// first two with the step's scalars, the pass sums the last two.
CLOTHSIM_SLOT kEventHardening = 15;  // SpringLimits::hardening
CLOTHSIM_SLOT kEventTime = 16;       // s, the step's end: when a connector that breaks now broke
CLOTHSIM_SLOT kEventFracture = 17;   // J: the elastic energy the breaks released (negative), fracture work
CLOTHSIM_SLOT kEventPlastic = 18;    // J: the elastic energy's change by yields and creases, plastic work
CLOTHSIM_SLOT kSolveReals = 19;

// solve_uint.
CLOTHSIM_SLOT kIterations = 0;     // CG iterations of this step's solve
CLOTHSIM_SLOT kSolveDone = 1;      // 1: the solve has stopped (the passes of further iterations return at once)
CLOTHSIM_SLOT kSolveConverged = 2; // 1: it stopped at the tolerance (or on a breakdown), 0: at kMaxIterations
CLOTHSIM_SLOT kMaxIterations = 3;  // cg_max_iterations
CLOTHSIM_SLOT kNonFiniteParticle = 4;  // the first free particle whose velocity change is not finite; kNoParticle: none
CLOTHSIM_SLOT kHolding = 5;        // 1: the step holds particles resting on obstacles (the host's surface contacts)
CLOTHSIM_SLOT kReleased = 6;       // 1: a held particle was let go after the solve (the surface would pull it)
CLOTHSIM_SLOT kStiffnessRatio = 7; // the V-cycle's level 0: the largest (trace A_pp - 3 m) / m, a float's bits
CLOTHSIM_SLOT kResting = 8;        // 1: the obstacle pass left a particle resting on a surface (the next step holds)
CLOTHSIM_SLOT kStateChanged = 9;   // 1: the obstacle pass changed a particle's state (the end's forces are stale)
CLOTHSIM_SLOT kEventBreaks = 10;   // connectors the laws broke after the step
CLOTHSIM_SLOT kEventYields = 11;   // connectors that yielded
CLOTHSIM_SLOT kEventCreases = 12;  // radial springs that creased
CLOTHSIM_SLOT kSolveUints = 13;
CLOTHSIM_SLOT kNoParticle = 0xffffffffu;

// The element factors (forces/element_jacobian.inc), Reals per element.
// Connector: direction (3), along, across, damping.
CLOTHSIM_SLOT kConnectorFactorReals = 6;
// Radial spring: gradients of the centre, b and c (9), in-plane stiffness, damping, transverse axis
// (3), straight (1 or 0), sum and difference tilts (3 each), equal and opposite couplings.
CLOTHSIM_SLOT kRadialFactorReals = 23;

// surface_contacts: per particle, the surface it rests on at the step's start (model/surface_contacts.h):
// its unit normal (3), the surface's velocity (3), the friction coefficient, and at kContactResting
// the collider's index + 1 where it rests on one (0 where not, and for anchored particles).
CLOTHSIM_SLOT kContactReals = 8;
CLOTHSIM_SLOT kContactResting = 7;
// hold: per particle, the directions the step holds (integrators/held_directions.h's Hold).
CLOTHSIM_SLOT kHoldNone = 0;
CLOTHSIM_SLOT kHoldNormal = 1;
CLOTHSIM_SLOT kHoldAll = 2;

// anchor_rows: per anchor, its particle's position, velocity and acceleration on the path at the
// step's end, written by the host.
CLOTHSIM_SLOT kAnchorRowReals = 9;

// implicit_setup's phases, in the order a step runs them.
CLOTHSIM_SLOT kSetupDisplacement = 0;  // direction = z (h v, or an anchor's path displacement); anchors' known dv
CLOTHSIM_SLOT kSetupWarmStart = 1;     // direction = the unknown dv (the warm start, anchors' known values)
CLOTHSIM_SLOT kSetupCheck = 2;         // the first free particle with a non-finite dv
CLOTHSIM_SLOT kSetupUpdate = 3;        // v += dv, x += h v (unless non-finite); anchors on their paths
CLOTHSIM_SLOT kSetupPowers = 4;        // each workgroup's damping, drag and anchor power at the step's end

// implicit_gather's modes: what it makes of each particle's product (element slots plus mass and drag).
CLOTHSIM_SLOT kGatherRightHandSide = 0;  // b = h (f0 - K z) from the product K z
CLOTHSIM_SLOT kGatherResidual = 1;       // r = b - A u, z = P r, direction = z; partials r.z, r.r, b.b
CLOTHSIM_SLOT kGatherProduct = 2;        // q = A p; partial p.q
CLOTHSIM_SLOT kGatherImpulse = 3;        // a held particle's surface impulse A dv - b (its normal part where
                                         // held along the normal), zero where not held

// implicit_product's operators.
CLOTHSIM_SLOT kProductStiffness = 0;  // K alone (for K z)
CLOTHSIM_SLOT kProductSystem = 1;     // A's element part, h C + h^2 K (mass and drag are the gather's)

// implicit_diagonal's phases.
CLOTHSIM_SLOT kDiagonalHold = 0;     // the block Jacobi inverses, and which particles the step holds on their surface
CLOTHSIM_SLOT kDiagonalRelease = 1;  // after the solve: let go of those the surface would pull, mark those that slip

// implicit_iterate's phases, and implicit_reduce's.
CLOTHSIM_SLOT kIterateUpdate = 0;     // u += alpha p, r -= alpha q, z = P r; partials r.z, r.r
CLOTHSIM_SLOT kIterateDirection = 1;  // p = z + beta p
CLOTHSIM_SLOT kIterateStart = 2;      // with the V-cycle's z (gpu/device_multigrid.h): p = z; partials r.z, r.r, b.b
CLOTHSIM_SLOT kIterateSums = 3;       // with the V-cycle's z: partials r.z, r.r
CLOTHSIM_SLOT kIterateAdvance = 4;    // with the V-cycle: u += alpha p, r -= alpha q (no z, no partials)
CLOTHSIM_SLOT kReduceStart = 0;       // r.z, r.r, b.b of the first residual: the target, or done
CLOTHSIM_SLOT kReduceCurvature = 1;   // p.q: alpha (or done on a breakdown)
CLOTHSIM_SLOT kReduceResidual = 2;    // r.z, r.r: done, or beta
CLOTHSIM_SLOT kReducePowers = 3;      // the step's end powers
CLOTHSIM_SLOT kReduceObstacles = 4;   // the obstacle pass's blocks (obstacle_energy_elements): work, moved, arrival
CLOTHSIM_SLOT kReduceEvents = 5;      // the spring laws' blocks (implicit_events): fracture and plastic work

// implicit_events' phases, one dispatch each, writing their workgroups' sums at first_block on.
CLOTHSIM_SLOT kEventsConnectorsPhase = 0;  // tearing, then permanent stretching, per connector
CLOTHSIM_SLOT kEventsRadialsPhase = 1;     // a radial spring breaks with an arm, else creases
// connector_events: per connector, kEventsPerConnector Reals at device_step.h's kEvent* offsets
// (original length, break strain, yield strain, the time it broke).

struct EventElementConstants {
  uint count;        // connectors or radial springs
  uint phase;        // kEvents*Phase
  uint first_block;  // where the phase's workgroups write their sums in block_sums
  uint laws;         // device_step.h's kLawTearing | kLawPlasticity | kLawCreasing: the laws that act
};

struct ImplicitPassConstants {
  uint particle_count;
  uint connector_count;
  uint radial_count;
  uint radial_slot_base;  // the first radial spring's force slot
  uint phase;             // the pass's phase, mode or operator (above)
  uint blocks;            // workgroups of the partial sums' pass (implicit_reduce), or of this pass
  uint element_count;     // connectors + radial springs (kSetupPowers sums their damping powers)
  uint damped;            // 1: the springs' damping acts (kSpringDamping)
  uint iteration;         // 1: a pass of a CG iteration, which returns at once once the solve has stopped
};

// The workgroup size of the passes that write partial sums (implicit_gather, implicit_iterate,
// implicit_setup's powers) and of implicit_reduce: fixed, because their shared arrays are.
CLOTHSIM_SLOT kImplicitReduceWorkgroup = 256;

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
