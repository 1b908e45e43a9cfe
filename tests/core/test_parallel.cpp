// Thread-count resolution and parallel_for: every index visited exactly once for any thread count.
#include <gtest/gtest.h>

#include <sched.h>

#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "core/parallel.h"

namespace clothsim {
namespace {

TEST(Parallel, ExplicitThreadCountsAreKept) {
  EXPECT_EQ(resolve_thread_count(3, 10), 3);
  EXPECT_EQ(resolve_thread_count(1, 1'000'000), 1);
}

TEST(Parallel, ChosenCountIsOneForSmallProblemsAndAtMostTheHardwareOtherwise) {
  EXPECT_EQ(resolve_thread_count(0, 100, 4096), 1);
  // Above the threshold it takes the idle threads it is given (so a chooser stuck at 1 fails here).
  EXPECT_EQ(resolve_thread_count(0, 1'000'000, 4096, 2), 2);
  EXPECT_EQ(resolve_thread_count(0, 4096, 4096, 2), 2);
  const int chosen = resolve_thread_count(0, 1'000'000, 4096);
  EXPECT_GE(chosen, 1);
  EXPECT_LE(chosen, hardware_thread_count());
  EXPECT_GE(idle_hardware_threads(), 1);
  EXPECT_LE(idle_hardware_threads(), hardware_thread_count());
}

// A caller that samples the idle cores once (the benchmark suite) passes them in; small problems
// and explicit requests are unaffected.
TEST(Parallel, GivenAvailableThreadsReplaceTheLoadSample) {
  EXPECT_EQ(resolve_thread_count(0, 5000, kParallelThreshold, 3), 3);
  EXPECT_EQ(resolve_thread_count(0, 100, kParallelThreshold, 3), 1);
  EXPECT_EQ(resolve_thread_count(2, 5000, kParallelThreshold, 3), 2);
}

// The automatic choice counts what runs now: /proc/stat's procs_running (which counts the
// caller), read from the text as the kernel writes it, less the caller, taken from the CPUs the
// process may use.
TEST(Parallel, IdleThreadsAreTheAllowedCpusLessWhatRunsNow) {
  const std::string stat =
      "cpu  10 0 5 100 0 0 0 0 0 0\ncpu0 5 0 2 50 0 0 0 0 0 0\nctxt 42\nbtime 1796225986\nprocesses 7438\n"
      "procs_running 3\nprocs_blocked 0\n";
  EXPECT_EQ(parse_procs_running(stat), 3);
  EXPECT_EQ(parse_procs_running("cpu  1 2 3\nprocs_blocked 0\n"), -1);
  EXPECT_EQ(parse_procs_running("cpu  1 2 3\nprocs_running x\n"), -1);
  EXPECT_EQ(idle_threads(16, 0), 16);  // an idle machine: every allowed CPU
  EXPECT_EQ(idle_threads(16, 5), 11);
  EXPECT_EQ(idle_threads(2, 1), 1);
  EXPECT_EQ(idle_threads(2, 7), 1);  // never below one thread
  EXPECT_EQ(idle_threads(4, -1), 4);
}

// The CPUs counted are the affinity mask's, not the machine's: a process pinned to one CPU
// (taskset, a container's cpuset) gets one thread.
TEST(Parallel, TheHardwareIsTheAffinityMask) {
  cpu_set_t saved;
  ASSERT_EQ(sched_getaffinity(0, sizeof(saved), &saved), 0);
  EXPECT_EQ(hardware_thread_count(), CPU_COUNT(&saved));
  int first = 0;
  while (!CPU_ISSET(first, &saved)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  const int pinned = hardware_thread_count();
  const int idle = idle_hardware_threads();
  ASSERT_EQ(sched_setaffinity(0, sizeof(saved), &saved), 0);
  EXPECT_EQ(pinned, 1);
  EXPECT_EQ(idle, 1);
}

// parallel_for and parallel_for_dynamic, each on its own.
TEST(Parallel, ParallelForVisitsEveryIndexOnce) {
  const auto check = [](const char* name, auto&& loop) {
    for (int threads : {1, 2, 3, 4}) {
      std::vector<std::atomic<int>> visits(1001);
      loop(visits.size(), threads, [&](std::size_t i) { visits[i].fetch_add(1); });
      for (std::size_t i = 0; i < visits.size(); ++i)
        EXPECT_EQ(visits[i].load(), 1) << name << ": " << i << ", " << threads << " threads";
    }
  };
  check("parallel_for", [](std::size_t n, int threads, auto&& body) { parallel_for(n, threads, body); });
  check("parallel_for_dynamic",
        [](std::size_t n, int threads, auto&& body) { parallel_for_dynamic(n, threads, body); });
}

// Against the serial loop, on counts that end inside a block, on a block's edge and past several.
TEST(Parallel, MaxAndSelectAreTheSerialLoopsForAnyThreadCount) {
  for (std::size_t count : {std::size_t{0}, std::size_t{1}, kParallelBlock, 3 * kParallelBlock + 17}) {
    const auto value = [](std::size_t i) {
      return std::sin(0.37 * static_cast<double>(i)) * static_cast<double>(i % 97);
    };
    const auto keep = [&](std::size_t i) { return value(i) > 10.0; };
    double largest = -1.0;
    std::vector<std::uint32_t> kept;
    for (std::size_t i = 0; i < count; ++i) {
      largest = std::max(largest, value(i));
      if (keep(i)) kept.push_back(static_cast<std::uint32_t>(i));
    }
    for (int threads : {1, 2, 3, 4}) {
      EXPECT_EQ(parallel_max(count, threads, value, -1.0), largest) << count << ", " << threads << " threads";
      std::vector<std::uint32_t> selected(5, 7);  // replaced, not appended to
      parallel_select(count, threads, keep, selected);
      EXPECT_EQ(selected, kept) << count << ", " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace clothsim
