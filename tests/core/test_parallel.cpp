// Thread-count resolution and parallel_for: every index visited exactly once for any thread count.
#include <gtest/gtest.h>

#include <atomic>
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

TEST(Parallel, ParallelForVisitsEveryIndexOnce) {
  for (int threads : {1, 2, 3, 4}) {
    std::vector<std::atomic<int>> visits(1001);
    parallel_for(visits.size(), threads, [&](std::size_t i) { visits[i].fetch_add(1); });
    for (std::size_t i = 0; i < visits.size(); ++i)
      EXPECT_EQ(visits[i].load(), 1) << i << ", " << threads << " threads";
  }
}

}  // namespace
}  // namespace clothsim
