// Three sums over a workgroup (or two sums and a least value), in a tree in shared memory: the same
// operations in the same order whatever the scheduling, so a result is the same on every run on a
// device. The one reduction of every pass that reduces per workgroup (the implicit step's, rk_accept,
// rk_control, obstacle_energy, lattice_events_radial). The includer declares kWorkgroupSize, a
// constant power of two (not a specialization constant: the shared array's size).
#ifndef CLOTHSIM_WORKGROUP_SUMS_GLSL
#define CLOTHSIM_WORKGROUP_SUMS_GLSL

shared Real workgroup_sum[3][kWorkgroupSize];

// Every invocation of the workgroup calls it with its three values; the results are then in
// workgroup_sum[k][0] for every invocation to read: sums, or for the third the least value where
// `third_is_least`.
void reduce_over_workgroup(Real values[3], bool third_is_least) {
  const uint i = gl_LocalInvocationID.x;
  barrier();  // workgroup_sum is free: a reduction before this one has been read
  for (uint k = 0u; k < 3u; ++k) workgroup_sum[k][i] = values[k];
  barrier();
  for (uint stride = kWorkgroupSize / 2u; stride > 0u; stride /= 2u) {
    if (i < stride) {
      workgroup_sum[0][i] += workgroup_sum[0][i + stride];
      workgroup_sum[1][i] += workgroup_sum[1][i + stride];
      workgroup_sum[2][i] = third_is_least ? min(workgroup_sum[2][i], workgroup_sum[2][i + stride])
                                           : workgroup_sum[2][i] + workgroup_sum[2][i + stride];
    }
    barrier();
  }
}

void sum_over_workgroup(Real values[3]) { reduce_over_workgroup(values, false); }

#endif
