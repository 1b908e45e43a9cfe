// The largest scaled error of a workgroup, and the first particle that has it (rk_solution and
// lattice_stage over particles, rk_control over the workgroups' results): a tree in shared
// memory, whose result does not depend on scheduling. Non-finite values count as kHugeError,
// above every finite error, as the CPU's bit-pattern maximum lets NaN win. The workgroup has
// CLOTHSIM_REDUCE_SIZE invocations, a power of two (kReduceWorkgroup unless the includer defines
// it).
#ifndef CLOTHSIM_ERROR_REDUCTION_GLSL
#define CLOTHSIM_ERROR_REDUCTION_GLSL
#ifndef CLOTHSIM_REDUCE_SIZE
#define CLOTHSIM_REDUCE_SIZE kReduceWorkgroup
#endif

// Above every finite error a step can have (finite ratios are capped just below it) and within
// float's range.
const Real kHugeError = Real(1e30);

Real bounded_error(Real ratio, Vec3 x, Vec3 v) {
  const bool finite = !(isnan(ratio) || isinf(ratio) || any(isnan(x)) || any(isinf(x)) || any(isnan(v)) ||
                        any(isinf(v)));
  return finite ? min(ratio, Real(0.5) * kHugeError) : kHugeError;
}

shared Real largest_error[CLOTHSIM_REDUCE_SIZE];
shared uint largest_particle[CLOTHSIM_REDUCE_SIZE];

// Every invocation of the workgroup calls it; the result is in largest_error[0] and
// largest_particle[0].
void reduce_largest_error(Real error, uint particle) {
  const uint i = gl_LocalInvocationID.x;
  largest_error[i] = error;
  largest_particle[i] = particle;
  barrier();
  for (uint stride = CLOTHSIM_REDUCE_SIZE / 2u; stride > 0u; stride /= 2u) {
    if (i < stride) {
      const Real other = largest_error[i + stride];
      const uint other_particle = largest_particle[i + stride];
      if (other > largest_error[i] || (other == largest_error[i] && other_particle < largest_particle[i])) {
        largest_error[i] = other;
        largest_particle[i] = other_particle;
      }
    }
    barrier();
  }
}

#endif
