// CLOTHSIM_MULTIVERSION: compile a hot function three times, for AVX-512 (x86-64-v4), AVX2
// (x86-64-v3) and the baseline x86-64, and let the dynamic loader pick the best one the CPU
// supports (GCC function multiversioning through an ifunc resolver). This is safe on any x86-64
// machine, unlike -march=native in the build, and the binary still uses AVX-512 where it exists.
//
// The versions compute bit-identical results: -ffp-contract=off (CMakeLists.txt) keeps fused
// multiply-adds out of the AVX2 and AVX-512 code, and every vector lane performs the same
// correctly rounded IEEE operations as the baseline code. Put it on non-template, non-inline
// functions with internal or external linkage; functions they call should be inlined (mark them
// [[gnu::always_inline]]) so that they are compiled into each version. A lambda is a function of
// its own: one defined inside a multiversioned function (or a parallel_for's body) is compiled
// once, for the baseline, and called from every version, so the hot work must not sit in one.
// `nm -C` on the binary shows it: a version that is a few hundred bytes is only a call.
//
// Elsewhere (other compilers or architectures) it expands to nothing.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLOTHSIM_MULTIVERSION __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CLOTHSIM_MULTIVERSION
#endif
