#version 450
#extension GL_GOOGLE_include_directive : require
// The step's decisions on the device, in one workgroup, so that no step waits for the host.
//
// Phase 0, after rk_solution: the largest error over rk_solution's workgroups, then
// AdaptiveRungeKutta::step's decision: reject and shrink (a step underflow below min_step ends
// the advance as failed), or accept, with the PI controller's next step and the time advanced; a
// fixed-step method accepts every finite step. Then the next attempt's step, clipped to land on
// its limit: the target, or an impact on an obstacle ahead (kArrival), as the Simulation limits a
// step on the CPU. The controller and the clipping are the CPU's, integrators/step_control.inc;
// its factors are computed in float here: GLSL's pow exists for float only, and a step-size
// factor needs no more.
//
// Phase 1, after rk_accept: the accepted step's work (damping, drag, anchor), summed over
// rk_accept's workgroups in a fixed order, added to the advance's compensated sums; with
// obstacles, the obstacle passes' work, contacts and earliest arrival too, and only then the next
// step, which the arrival limits. Without obstacles phase 1 has no dispatch of its own: the next
// attempt's phase 0 adds the step's work before deciding, and phase 3, after a submission's last
// attempt, adds the last step's and marks it added; the same sums in the same order. Phase 2,
// after lattice_events_radial: the events' fracture and plastic work, the same way.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"
#define StepFactor float
#include "integrators/step_control.inc"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) buffer ControlReal { Real control_real[]; };
layout(std430, binding = 1) buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 2) readonly buffer BlockError { Real block_error[]; };
layout(std430, binding = 3) readonly buffer BlockParticle { uint block_particle[]; };
layout(std430, binding = 4) readonly buffer BlockWork { Real block_work[]; };  // [blocks][3]
layout(std430, binding = 5) readonly buffer BlockEvents { Real block_events[]; };  // [blocks][2]
layout(std430, binding = 6) readonly buffer BlockObstacles { Real block_obstacles[]; };  // [blocks][3]

layout(push_constant) uniform Constants { ReducePassConstants constants; };

#include "gpu/shaders/error_reduction.glsl"

// Ends the advance as failed.
void fail(uint status, uint particle, bool non_finite) {
  control_uint[kStatus] = status;
  control_uint[kFailedParticle] = particle;
  control_uint[kNonFiniteError] = non_finite ? 1u : 0u;
  control_uint[kActive] = 0u;
}

// The controller as the control arrays keep it.
StepController load_controller() {
  StepController controller;
  controller.safety = StepFactor(control_real[kSafety]);
  controller.max_growth = StepFactor(control_real[kMaxGrowth]);
  controller.max_shrink = StepFactor(control_real[kMaxShrink]);
  controller.proposed_step = control_real[kProposedStep];
  controller.previous_error = control_real[kPreviousError];
  controller.rejected_before = control_uint[kRejectedBefore] != 0u;
  return controller;
}

void store_controller(StepController controller) {
  control_real[kProposedStep] = controller.proposed_step;
  control_real[kPreviousError] = controller.previous_error;
  control_uint[kRejectedBefore] = controller.rejected_before ? 1u : 0u;
}

// The next attempt's step, stretched to end on its limit (the target, or an impact ahead) when it
// would stop just short of it.
void propose_step() {
  if (control_uint[kActive] == 0u) return;
  const bool adaptive = control_uint[kAdaptive] != 0u;
  const Real step = adaptive ? min(control_real[kProposedStep], control_real[kMaxStep]) : control_real[kFixedStep];
  const Real limit = min(control_real[kTarget], control_real[kArrival]);
  const ClippedStep next = clip_step(control_real[kElapsed], step, limit);
  control_real[kStep] = next.step;
  control_real[kStepLimit] = limit;
  control_uint[kClipped] = next.clipped ? 1u : 0u;
  if (adaptive && next.step < control_real[kMinStep] && !next.clipped) fail(1u, 0u, false);
}

void decide(Real error, uint worst) {
  control_uint[kAttempts] += 1u;
  control_uint[kWorstParticle] = worst;
  control_real[kError] = error;
  const Real h = control_real[kStep];
  const bool clipped = control_uint[kClipped] != 0u;
  const bool adaptive = control_uint[kAdaptive] != 0u;
  const bool non_finite = error >= kHugeError;
  control_uint[kAccepted] = 0u;
  if (adaptive && error > Real(1.0)) {
    control_uint[kRejectedSteps] += 1u;
    StepController controller = load_controller();
    reject_step(controller, h, error, non_finite);
    store_controller(controller);
    if (controller.proposed_step < control_real[kMinStep]) fail(1u, worst, non_finite);
  } else if (!adaptive && non_finite) {
    fail(2u, worst, true);
  } else {
    if (adaptive) {
      StepController controller = load_controller();
      accept_step(controller, h, error, clipped);
      store_controller(controller);
    }
    control_real[kStepStart] = control_real[kElapsed];
    control_real[kElapsed] = clipped ? control_real[kStepLimit] : control_real[kElapsed] + h;
    control_real[kTakenStep] = h;
    control_real[kSmallestStep] = min(control_real[kSmallestStep], h);
    control_real[kLargestStep] = max(control_real[kLargestStep], h);
    control_uint[kAccepted] = 1u;
    control_uint[kAcceptedSteps] += 1u;
    control_uint[kRejectedBefore] = 0u;
    const uint limit = control_uint[kMaxAccepted];
    const bool at_target = clipped && control_real[kStepLimit] == control_real[kTarget];
    if (at_target || (limit != 0u && control_uint[kAcceptedSteps] >= limit)) control_uint[kActive] = 0u;
    // With obstacles, the next step waits for phase 1: the step just taken moves the arrival.
    if (constants.obstacles != 0u) return;
  }
  propose_step();
}

// sum + value as a compensated (Kahan) sum kept in control_real[slot] and [slot + 1].
void add_compensated(uint slot, Real value) {
  precise Real y = value - control_real[slot + 1];
  precise Real t = control_real[slot] + y;
  control_real[slot + 1] = (t - control_real[slot]) - y;
  control_real[slot] = t;
}

#include "gpu/shaders/workgroup_sums.glsl"

// Work k of block `block`: the step's three from rk_accept (phase 1), or the events' two (phase 2).
Real block_value(uint phase, uint block, uint k) {
  return phase == 1u ? block_work[3u * block + k] : block_events[2u * block + k];
}

// Phase 1's or phase 2's work over `blocks` workgroups, into the advance's compensated sums.
void collect_work(uint phase, uint blocks) {
  const uint i = gl_LocalInvocationID.x;
  const uint count = phase == 1u ? 3u : 2u;
  const uint first = phase == 1u ? 0u : 3u;  // damping, drag, anchor; then fracture, plastic
  Real sums[3] = Real[3](Real(0.0), Real(0.0), Real(0.0));
  for (uint block = i; block < blocks; block += kReduceWorkgroup) {
    for (uint k = 0u; k < count; ++k) sums[k] += block_value(phase, block, k);
  }
  reduce_over_workgroup(sums, false);
  if (i == 0u) {
    for (uint k = 0u; k < count; ++k) add_compensated(kWork + 2u * (first + k), workgroup_sum[k][0]);
  }
}

// The obstacle passes' results (obstacle_energy): the contact work into its compensated sum, the
// particles moved, and the arrival limit from the step's end (ObstacleContacts::begin_step: none
// when it rounds to the current time).
void collect_obstacles() {
  const uint i = gl_LocalInvocationID.x;
  Real partial[3] = Real[3](Real(0.0), Real(0.0), Real(CLOTHSIM_NO_ARRIVAL));
  for (uint block = i; block < constants.blocks; block += kReduceWorkgroup) {
    partial[0] += block_obstacles[kObstacleBlockReals * block];
    partial[1] += block_obstacles[kObstacleBlockReals * block + 1u];
    partial[2] = min(partial[2], block_obstacles[kObstacleBlockReals * block + 2u]);
  }
  reduce_over_workgroup(partial, true);
  if (i == 0u) {
    add_compensated(kWork + 2u * kContactWork, workgroup_sum[0][0]);
    const uint contacts = uint(workgroup_sum[1][0]);
    control_uint[kContacts] = contacts;
    control_uint[kContactSteps] += contacts;
    control_uint[kMostContacts] = max(control_uint[kMostContacts], contacts);
    const Real elapsed = control_real[kElapsed];
    const Real earliest = workgroup_sum[2][0];  // s from now
    const Real arrival = elapsed + earliest;
    const bool limits = earliest < Real(CLOTHSIM_NO_ARRIVAL) && arrival > elapsed;
    control_real[kArrival] = limits ? arrival : Real(CLOTHSIM_NO_ARRIVAL);
    propose_step();
  }
}

void main() {
  if (constants.phase != 0u) {
    if (control_uint[kAccepted] == 0u) return;  // the same for the whole workgroup
    collect_work(constants.phase == 2u ? 2u : 1u, constants.blocks);
    if (constants.phase == 1u && constants.obstacles != 0u) collect_obstacles();
    if (constants.phase == 3u && gl_LocalInvocationID.x == 0u) control_uint[kAccepted] = 0u;  // added
    return;
  }
  // The step accepted before this attempt, whose work rk_accept left (phase 1's, without obstacles).
  const bool pending = constants.work_blocks != 0u && control_uint[kAccepted] != 0u;
  barrier();  // every invocation has read the flag before the decision rewrites it
  if (pending) collect_work(1u, constants.work_blocks);
  if (control_uint[kActive] == 0u) {
    if (gl_LocalInvocationID.x == 0u) control_uint[kAccepted] = 0u;
    return;
  }
  const uint i = gl_LocalInvocationID.x;
  Real error = Real(0.0);
  uint worst = 0xffffffffu;
  for (uint block = i; block < constants.blocks; block += kReduceWorkgroup) {
    const Real e = block_error[block];
    if (e > error || (e == error && block_particle[block] < worst)) {
      error = e;
      worst = block_particle[block];
    }
  }
  reduce_largest_error(error, worst);
  if (i == 0u) decide(largest_error[0], largest_particle[0]);
}
