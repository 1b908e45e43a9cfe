// An estimate of the largest stable step of the fixed-step explicit integrators on a model, so
// that a run can warn before it blows up (issue 11).
//
// The linearised system's fastest rates are bounded per particle by Gershgorin's circle theorem
// on M^-1 K and M^-1 C: omega^2 <= (sum_j |K_ij|) / m and gamma <= (sum_j |C_ij|) / m, summed over
// the springs at the particle (a connector's row sums to 2 k; an angle spring's, at rest, to
// k |g_i| sum_j |g_j| with g the angle's gradient, 1/L at an arm's end). A step is stable when
// h omega and h gamma are inside the method's stability region on the imaginary and the negative
// real axis: 2.83 and 2.79 for classical RK4, 2 and 2 for symplectic Euler. The rates are upper
// bounds, so the estimate errs on the safe side (tested: the paper's sheet runs at the estimate
// and blows up at a few times it).
#pragma once

#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim {

struct StableStep {
  double step = 0.0;         // s; +infinity for RKF45 and implicit Euler (no fixed-step limit)
  std::size_t particle = 0;  // where the fastest rate is
};

StableStep estimate_stable_step(const ClothModel& model, IntegratorKind kind);

}  // namespace clothsim
