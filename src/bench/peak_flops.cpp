#include "bench/peak_flops.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstddef>

#include "core/multiversion.h"
#include "core/timer.h"

namespace clothsim {
namespace {

constexpr std::size_t kChains = 128;
constexpr int kRepetitions = 5;
// a -> a s + t converges to t / (1 - s) = 1 from any start: no overflow, no subnormals.
constexpr double kScale = 0.999;
constexpr double kOffset = 0.001;

CLOTHSIM_MULTIVERSION void multiply_add_rounds(double* __restrict chains, long rounds) {
  std::array<double, kChains> a;
  std::copy(chains, chains + kChains, a.begin());
  for (long round = 0; round < rounds; ++round) {
#pragma GCC ivdep
    for (std::size_t k = 0; k < kChains; ++k) a[k] = a[k] * kScale + kOffset;
  }
  std::copy(a.begin(), a.end(), chains);
}

}  // namespace

double measure_peak_gflops(int threads) {
  threads = std::max(1, threads);
  // Rounds of one repetition: about 20 ms at 50 GFLOP/s per thread.
  constexpr long kRounds = 4'000'000;
  double best = 0.0;
  double checksum = 0.0;
  for (int repetition = 0; repetition < kRepetitions; ++repetition) {
    const Stopwatch watch;
#pragma omp parallel num_threads(threads) reduction(+ : checksum)
    {
      std::array<double, kChains> chains;
      for (std::size_t k = 0; k < kChains; ++k) chains[k] = static_cast<double>(k) / kChains;
      multiply_add_rounds(chains.data(), kRounds);
      for (double value : chains) checksum += value;
    }
    const double seconds = watch.seconds();
    const double flops = 2.0 * static_cast<double>(kChains) * static_cast<double>(kRounds) * threads;
    if (seconds > 0.0) best = std::max(best, flops / seconds / 1e9);
  }
  // The chains' values are used, so the loop cannot be dropped: each converges to 1.
  return checksum > 0.0 ? best : 0.0;
}

}  // namespace clothsim
