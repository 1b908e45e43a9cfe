// Data-parallel loops over index ranges.
//
// The loops are OpenMP with a static schedule. Every loop body in clothsim writes only to slots
// owned by its index, and every reduction runs over fixed-size blocks summed in index order, so
// results are bit-for-bit identical for any thread count (see docs/architecture.md).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

namespace clothsim {

// Resolves a requested thread count: 0 means "choose", which picks 1 thread for problems with
// fewer than `parallel_threshold` items (thread start-up costs more than it saves on small
// sheets) and otherwise the CPUs this process may run on that other work leaves idle now
// (idle_hardware_threads()). A loop split over more threads than there are free cores waits at
// every barrier for a thread that is not running: on a busy 2-core machine a 2-thread force
// evaluation took 20-60 ms instead of 0.5 ms (docs/performance.md). The choice never changes
// results, which are the same for any thread count. `available` > 0 replaces idle_hardware_threads()
// (a caller that makes many choices in a row samples once, before its own threads add to the load).
inline constexpr std::size_t kParallelThreshold = 4096;  // items; below it the automatic choice is 1 thread
int resolve_thread_count(int requested, std::size_t problem_size, std::size_t parallel_threshold = kParallelThreshold,
                         int available = 0);
// The CPUs this process may run on (its affinity mask: `taskset`, a container's cpuset), at least 1.
int hardware_thread_count();
// hardware_thread_count() less the threads other than the caller that are running or waiting to
// run now (/proc/stat's procs_running, the least of a few samples a millisecond apart, so a
// process that merely flickers past is not counted), at least 1; all of them where that cannot be
// read. Sampled now, not averaged: the 1-minute load average stays near 1 for a minute after a
// run ends, and talked the next run on an idle machine down to 1 thread.
int idle_hardware_threads();
// The rule behind idle_hardware_threads(), apart from the sampling: `available` CPUs less
// `other_runnable` threads, clamped to [1, available].
int idle_threads(int available, int other_runnable);
// procs_running from the text of /proc/stat, or -1 where it has none.
int parse_procs_running(std::string_view proc_stat);

template <typename Body>
void parallel_for(std::size_t count, int threads, Body&& body) {
  if (threads <= 1) {
    // A plain loop: even a serialised OpenMP region costs a runtime call per loop.
    for (std::size_t i = 0; i < count; ++i) body(i);
    return;
  }
  const auto n = static_cast<long long>(count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long i = 0; i < n; ++i) {
    body(static_cast<std::size_t>(i));
  }
}

// The sums over i in [0, count) of the N components that term(i) returns (an std::array<double, N>),
// over fixed blocks of kSumBlock items, each added in index order, and the blocks added in block
// order: bit-for-bit the same for any thread count.
inline constexpr std::size_t kSumBlock = 4096;
template <std::size_t N, typename Term>
std::array<double, N> parallel_sum(std::size_t count, int threads, Term&& term) {
  const std::size_t blocks = (count + kSumBlock - 1) / kSumBlock;
  std::vector<std::array<double, N>> block_sums(blocks);
  parallel_for(blocks, threads, [&](std::size_t block) {
    std::array<double, N> sum{};
    const std::size_t end = std::min(count, (block + 1) * kSumBlock);
    for (std::size_t i = block * kSumBlock; i < end; ++i) {
      const std::array<double, N> value = term(i);
      for (std::size_t k = 0; k < N; ++k) sum[k] += value[k];
    }
    block_sums[block] = sum;
  });
  std::array<double, N> total{};
  for (const std::array<double, N>& sum : block_sums) {
    for (std::size_t k = 0; k < N; ++k) total[k] += sum[k];
  }
  return total;
}

}  // namespace clothsim
