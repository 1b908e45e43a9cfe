// The device's exclusive prefix sum (gpu/prefix_scan.h) against std::exclusive_scan: no values,
// one, a block less one, a block, a block and one, and counts of several hundred blocks, whose
// totals one workgroup scans in several chunks; the capacity larger than the count, and the values
// past the count left as they were.
#include "gpu/prefix_scan.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "gpu_fixture.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::GpuTest;

TEST_F(GpuTest, PrefixScanIsTheExclusiveSum) {
  testing::TestRandom random(5);
  constexpr std::uint32_t kCapacity = 300'000;
  gpu::PrefixScan scan(device(), kCapacity);
  gpu::Buffer values(device(), kCapacity * sizeof(std::uint32_t), gpu::Memory::device_local);
  scan.bind(values);
  for (const std::uint32_t count : {0u, 1u, 255u, 256u, 257u, 70'000u, 299'999u}) {
    std::vector<std::uint32_t> input(kCapacity);
    for (std::uint32_t& v : input) v = static_cast<std::uint32_t>(random.uniform(0.0, 7.0));
    gpu::upload(device(), values, std::as_bytes(std::span(input)));
    device().submit([&](VkCommandBuffer commands) { scan.record(commands, count); });
    std::vector<std::uint32_t> output(kCapacity);
    gpu::download(device(), values, std::as_writable_bytes(std::span(output)));
    std::vector<std::uint32_t> expected(input);
    std::exclusive_scan(input.begin(), input.begin() + count, expected.begin(), 0u);
    EXPECT_EQ(output, expected) << count;
    std::vector<std::uint32_t> sums(gpu::PrefixScan::blocks_for(kCapacity) + 1);
    gpu::download(device(), scan.block_sums(), std::as_writable_bytes(std::span(sums)));
    EXPECT_EQ(sums[gpu::PrefixScan::blocks_for(count)], std::accumulate(input.begin(), input.begin() + count, 0u))
        << count;
  }
}

}  // namespace
}  // namespace clothsim
