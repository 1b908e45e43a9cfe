// A floating-point peak probe for the roofline of `clothsim bench` (perf/suite.h), like the memory
// bandwidth probe bench/stream.cpp: the rate of independent multiply-add chains,
// a[k] = a[k] s + t over 128 accumulators, vectorised (AVX-512, AVX2 or baseline SSE2, chosen at
// load time like the lattice kernel: core/multiversion.h). 128 chains hide the latency of the
// multiply and the add on 2 pipes each; they fit the 32 AVX-512 registers. No fused multiply-add
// (the build contracts none, -ffp-contract=off), so this is the peak the force kernel can reach:
// one multiply and one add per element and round, counted as 2 flops.
//
// In float32 (the lattice kernel's float32 forces) the same probe runs on floats: twice the lanes.
#pragma once

#include "core/precision.h"

namespace clothsim {

// GFLOP/s of additions and multiplications in `precision` on `threads` threads (>= 1), the best of
// a few repetitions of about 20 ms each; about 0.1 s in all (half that in float32).
double measure_peak_gflops(int threads, Precision precision = Precision::float64);

}  // namespace clothsim
