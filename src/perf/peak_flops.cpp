#include "perf/peak_flops.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstddef>

#include "core/multiversion.h"
#include "core/timer.h"

namespace clothsim {
namespace {

// 128 double chains, 256 float ones: the same 16 AVX-512 registers of independent chains either way.
template <typename Real>
constexpr std::size_t kChains = 128 * sizeof(double) / sizeof(Real);
constexpr int kRepetitions = 5;
// a -> a s + t converges to t / (1 - s) = 1 from any start: no overflow, no subnormals.
constexpr double kScale = 0.999;
constexpr double kOffset = 0.001;

template <typename Real>
[[gnu::always_inline]] inline void multiply_add_rounds_of(Real* __restrict chains, long rounds) {
  constexpr Real scale = static_cast<Real>(kScale);
  constexpr Real offset = static_cast<Real>(kOffset);
  std::array<Real, kChains<Real>> a;
  std::copy(chains, chains + kChains<Real>, a.begin());
  for (long round = 0; round < rounds; ++round) {
#pragma GCC ivdep
    for (std::size_t k = 0; k < kChains<Real>; ++k) a[k] = a[k] * scale + offset;
  }
  std::copy(a.begin(), a.end(), chains);
}

CLOTHSIM_MULTIVERSION void multiply_add_rounds(double* __restrict chains, long rounds) {
  multiply_add_rounds_of(chains, rounds);
}

CLOTHSIM_MULTIVERSION void multiply_add_rounds(float* __restrict chains, long rounds) {
  multiply_add_rounds_of(chains, rounds);
}

template <typename Real>
double measure_peak(int threads) {
  threads = std::max(1, threads);
  // Rounds of one repetition: about 20 ms at 50 GFLOP/s per thread (float64).
  constexpr long kRounds = 4'000'000;
  double best = 0.0;
  double checksum = 0.0;
  for (int repetition = 0; repetition < kRepetitions; ++repetition) {
    const Stopwatch watch;
#pragma omp parallel num_threads(threads) reduction(+ : checksum)
    {
      std::array<Real, kChains<Real>> chains;
      for (std::size_t k = 0; k < kChains<Real>; ++k) chains[k] = static_cast<Real>(k) / kChains<Real>;
      multiply_add_rounds(chains.data(), kRounds);
      for (Real value : chains) checksum += value;
    }
    const double seconds = watch.seconds();
    const double flops = 2.0 * static_cast<double>(kChains<Real>) * static_cast<double>(kRounds) * threads;
    if (seconds > 0.0) best = std::max(best, flops / seconds / 1e9);
  }
  // The chains' values are used, so the loop cannot be dropped: each converges to 1.
  return checksum > 0.0 ? best : 0.0;
}

}  // namespace

double measure_peak_gflops(int threads, Precision precision) {
  return precision == Precision::float64 ? measure_peak<double>(threads) : measure_peak<float>(threads);
}

}  // namespace clothsim
