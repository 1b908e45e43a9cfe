#version 450
#extension GL_GOOGLE_include_directive : require
// The conjugate gradients' scalars on the device (BlockSystem::solve on the CPU): one workgroup
// adds the partial sums the last pass wrote per workgroup, in a fixed order, and decides:
//   kReduceStart      the target (cg_tolerance |b|)^2; rho = r.z; done at once if |r|^2 is below it
//   kReduceCurvature  an iteration begins: alpha = rho / p.q, or done on a breakdown (p.q <= 0)
//   kReduceResidual   done at the target (or a non-finite residual), or after the iteration limit;
//                     else beta = r.z / rho for the next direction
//   kReducePowers     the step's end powers: damping, drag, anchor
//   kReduceObstacles  the obstacle pass's (obstacle_energy_elements): the contact work, the particles
//                     moved, and the earliest arrival, a least value
//   kReduceEvents     the spring laws' (implicit_events): the fracture and the plastic work
// Once done, every pass of the iterations left in the submission returns at once.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kImplicitReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;

layout(std430, binding = 0) readonly buffer BlockSums { Real block_sums[]; };  // [blocks][3]
layout(std430, binding = 1) buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 2) buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"

void finish(bool converged) {
  solve_uint[kSolveDone] = 1u;
  solve_uint[kSolveConverged] = converged ? 1u : 0u;
}

void main() {
  const bool obstacles = constants.phase == kReduceObstacles;
  const bool after_solve = constants.phase == kReducePowers || obstacles || constants.phase == kReduceEvents;
  if (!after_solve && solve_uint[kSolveDone] != 0u) return;
  const uint i = gl_LocalInvocationID.x;
  Real partial[3] = Real[3](Real(0.0), Real(0.0), obstacles ? Real(CLOTHSIM_NO_ARRIVAL) : Real(0.0));
  for (uint block = i; block < constants.blocks; block += kWorkgroupSize) {
    partial[0] += block_sums[3 * block];
    partial[1] += block_sums[3 * block + 1];
    partial[2] = obstacles ? min(partial[2], block_sums[3 * block + 2]) : partial[2] + block_sums[3 * block + 2];
  }
  reduce_over_workgroup(partial, obstacles);
  if (i != 0u) return;
  const Real first = workgroup_sum[0][0];
  const Real second = workgroup_sum[1][0];
  const Real third = workgroup_sum[2][0];
  if (constants.phase == kReduceStart) {
    const Real relative = solve_real[kRelativeResidual];
    solve_real[kTargetResidual] = relative * relative * third;
    solve_real[kRho] = first;
    solve_real[kResidualNorm2] = second;
    if (second <= solve_real[kTargetResidual]) finish(true);
  } else if (constants.phase == kReduceCurvature) {
    solve_uint[kIterations] += 1u;
    if (!(first > Real(0.0))) {
      finish(true);  // a breakdown: A p = 0 or non-finite; the iterate stays
    } else {
      solve_real[kAlpha] = solve_real[kRho] / first;
    }
  } else if (constants.phase == kReduceResidual) {
    solve_real[kResidualNorm2] = second;
    if (second <= solve_real[kTargetResidual] || isnan(second) || isinf(second)) {
      finish(true);
    } else if (solve_uint[kIterations] >= solve_uint[kMaxIterations]) {
      finish(false);
    } else {
      solve_real[kBeta] = first / solve_real[kRho];
      solve_real[kRho] = first;
    }
  } else if (constants.phase == kReduceEvents) {
    solve_real[kEventFracture] = first;
    solve_real[kEventPlastic] = second;
  } else if (obstacles) {
    solve_real[kObstacleWork] = first;
    solve_real[kObstacleMoved] = second;
    solve_real[kObstacleArrival] = third;
  } else {
    solve_real[kDampingPower] = first;
    solve_real[kDragPower] = second;
    solve_real[kAnchorPower] = third;
  }
}
