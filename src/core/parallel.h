// Data-parallel loops over index ranges.
//
// The loops are OpenMP with a static schedule. Every loop body in clothsim writes only to slots
// owned by its index, and every reduction runs over fixed-size blocks summed in index order, so
// results are bit-for-bit identical for any thread count (see docs/architecture.md).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
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

// parallel_for with the items handed out one at a time as threads come free (OpenMP's dynamic
// schedule), for a few items of very different cost (the self-collision search's blocks: a
// block of particles' queries takes several times a block of the grid's buckets). Each item
// writes only its own slots, as in parallel_for, so which thread took it changes nothing.
template <typename Body>
void parallel_for_dynamic(std::size_t count, int threads, Body&& body) {
  if (threads <= 1) {
    for (std::size_t i = 0; i < count; ++i) body(i);
    return;
  }
  const auto n = static_cast<long long>(count);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long long i = 0; i < n; ++i) {
    body(static_cast<std::size_t>(i));
  }
}

// The block-wise helpers below split [0, count) into fixed blocks of kParallelBlock items, never
// derived from the thread count, so that what they return is the same for any thread count.
inline constexpr std::size_t kParallelBlock = 4096;
inline constexpr std::size_t parallel_block_count(std::size_t count) {
  return (count + kParallelBlock - 1) / kParallelBlock;
}
// body(block, begin, end) for every block and its index range [begin, end), the blocks in parallel.
template <typename Body>
void parallel_for_blocks(std::size_t count, int threads, Body&& body) {
  parallel_for(parallel_block_count(count), threads, [&](std::size_t block) {
    body(block, block * kParallelBlock, std::min(count, (block + 1) * kParallelBlock));
  });
}

// The largest term(i) over i in [0, count), and `lowest` for none. A maximum is the same whatever
// the order it is taken in, so any split over the threads gives the same value.
template <typename Term>
double parallel_max(std::size_t count, int threads, Term&& term, double lowest) {
  const std::size_t blocks = parallel_block_count(count);
  if (threads <= 1 || blocks <= 1) {
    double largest = lowest;
    for (std::size_t i = 0; i < count; ++i) largest = std::max(largest, term(i));
    return largest;
  }
  std::vector<double> block_max(blocks, lowest);
  parallel_for_blocks(count, threads, [&](std::size_t block, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) block_max[block] = std::max(block_max[block], term(i));
  });
  return *std::max_element(block_max.begin(), block_max.end());
}

// The indices i in [0, count) with keep(i), ascending, into `out` (replacing what it held): each
// block counts its kept indices, then writes them from the sum of the counts before it, so `out`
// is the serial loop's whatever the threads. keep(i) is called twice for each i.
template <typename Keep>
void parallel_select(std::size_t count, int threads, Keep&& keep, std::vector<std::uint32_t>& out) {
  const std::size_t blocks = parallel_block_count(count);
  if (threads <= 1 || blocks <= 1) {
    out.clear();
    for (std::size_t i = 0; i < count; ++i) {
      if (keep(i)) out.push_back(static_cast<std::uint32_t>(i));
    }
    return;
  }
  std::vector<std::size_t> start(blocks + 1, 0);
  parallel_for_blocks(count, threads, [&](std::size_t block, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) start[block + 1] += keep(i) ? 1 : 0;
  });
  for (std::size_t block = 0; block < blocks; ++block) start[block + 1] += start[block];
  out.resize(start[blocks]);
  parallel_for_blocks(count, threads, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::size_t next = start[block];
    for (std::size_t i = begin; i < end; ++i) {
      if (keep(i)) out[next++] = static_cast<std::uint32_t>(i);
    }
  });
}

// The sums over i in [0, count) of the N components that term(i) returns (an std::array<double, N>),
// each block's added in index order and the blocks added in block order: bit-for-bit the same for
// any thread count.
template <std::size_t N, typename Term>
std::array<double, N> parallel_sum(std::size_t count, int threads, Term&& term) {
  std::vector<std::array<double, N>> block_sums(parallel_block_count(count));
  parallel_for_blocks(count, threads, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::array<double, N> sum{};
    for (std::size_t i = begin; i < end; ++i) {
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
