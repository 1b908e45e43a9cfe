// Three sums over a workgroup, in a tree in shared memory: the same additions in the same order
// whatever the scheduling, so a result is the same on every run on a device. The includer declares
// kWorkgroupSize, a constant power of two (not a specialization constant: the shared array's size).
#ifndef CLOTHSIM_WORKGROUP_SUMS_GLSL
#define CLOTHSIM_WORKGROUP_SUMS_GLSL

shared Real workgroup_sum[3][kWorkgroupSize];

// Every invocation of the workgroup calls it with its three values; the sums are then in
// workgroup_sum[k][0] for every invocation to read.
void sum_over_workgroup(Real values[3]) {
  const uint i = gl_LocalInvocationID.x;
  barrier();  // workgroup_sum is free: a sum before this one has been read
  for (uint k = 0u; k < 3u; ++k) workgroup_sum[k][i] = values[k];
  barrier();
  for (uint stride = kWorkgroupSize / 2u; stride > 0u; stride /= 2u) {
    if (i < stride) {
      for (uint k = 0u; k < 3u; ++k) workgroup_sum[k][i] += workgroup_sum[k][i + stride];
    }
    barrier();
  }
}

#endif
