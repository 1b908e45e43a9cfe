// The device's hashed grid of boxes (gpu/device_box_grid.h) against the CPU's BoxGrid
// (collision/box_grid.h), given the CPU's cell size: the same buckets, each holding the same
// entries (cell, box, lowest-cell bits) in the same order, the same boxes kept aside and the same
// extent. Random boxes, with and without a few far larger than the rest; a lattice sheet's
// triangles, flat and folded; no boxes.
#include "gpu/device_box_grid.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "collision/box_grid.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/box_grid.h"
#include "gpu_fixture.h"

namespace clothsim {
namespace {

using testing::GpuTest;

Box random_box(std::mt19937& random, double space, double largest) {
  std::uniform_real_distribution<double> where(-space, space);
  std::uniform_real_distribution<double> size(0.0, largest);
  const Vec3 low{where(random), where(random), where(random)};
  return {low, low + Vec3{size(random), size(random), size(random)}};
}

// A rows x cols sheet's triangles' boxes, folded about its middle column when `folded`.
std::vector<Box> sheet_boxes(int rows, int cols, bool folded) {
  const auto at = [&](int i, int j) {
    const double x = 0.01 * j;
    const double fold = 0.01 * (cols / 2);
    return folded && x > fold ? Vec3{2 * fold - x, 0.004, 0.01 * i} : Vec3{x, 0.0, 0.01 * i};
  };
  std::vector<Box> boxes;
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j + 1 < cols; ++j) {
      for (const auto& corners : {std::array{at(i, j), at(i + 1, j), at(i, j + 1)},
                                  std::array{at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}}) {
        Box box{corners[0], corners[0]};
        for (const Vec3& c : corners) {
          box.low = {std::min(box.low.x, c.x), std::min(box.low.y, c.y), std::min(box.low.z, c.z)};
          box.high = {std::max(box.high.x, c.x), std::max(box.high.y, c.y), std::max(box.high.z, c.z)};
        }
        boxes.push_back({box.low - Vec3{0.002, 0.002, 0.002}, box.high + Vec3{0.002, 0.002, 0.002}});
      }
    }
  }
  return boxes;
}

void expect_same_grid(gpu::Device& device, const std::vector<Box>& boxes) {
  BoxGrid grid;
  grid.build(boxes);
  std::vector<double> reals;
  for (const Box& b : boxes) reals.insert(reals.end(), {b.low.x, b.low.y, b.low.z, b.high.x, b.high.y, b.high.z});
  if (reals.empty()) reals.push_back(0.0);
  const std::vector<std::byte> bytes = gpu::real_bytes(reals, gpu::Precision::float64);
  gpu::Buffer buffer(device, bytes.size(), gpu::Memory::device_local);
  gpu::upload(device, buffer, bytes);
  gpu::DeviceBoxGrid on_device(device, gpu::Precision::float64, static_cast<std::uint32_t>(boxes.size()));
  on_device.build(buffer, static_cast<std::uint32_t>(boxes.size()), grid.cell_size());

  ASSERT_EQ(on_device.entry_count(), grid.entries().size());
  ASSERT_EQ(on_device.bucket_count(), grid.bucket_count());
  const std::vector<std::uint32_t> starts = on_device.bucket_starts();
  ASSERT_TRUE(std::equal(starts.begin(), starts.end(), grid.bucket_starts().begin(), grid.bucket_starts().end()));
  const std::vector<std::uint32_t> entries = on_device.entries_by_bucket();
  for (std::size_t e = 0; e < grid.entries().size(); ++e) {
    const BoxGrid::Entry& expected = grid.entries()[e];
    const std::uint32_t* entry = &entries[e * gpu::kEntryWords];
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_EQ(static_cast<std::int32_t>(entry[axis]), expected.cell[static_cast<std::size_t>(axis)]) << e;
    }
    ASSERT_EQ(entry[gpu::kEntryBox], expected.box) << e;
    ASSERT_EQ(entry[gpu::kEntryLowest], expected.lowest) << e;
  }
  const std::vector<std::uint32_t> oversize = on_device.oversize();
  EXPECT_TRUE(std::equal(oversize.begin(), oversize.end(), grid.oversize().begin(), grid.oversize().end()));
  if (!grid.entries().empty()) {
    const std::array<std::int32_t, 6> extent = on_device.extent();
    for (std::size_t axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(extent[axis], grid.extent()[0][axis]);
      EXPECT_EQ(extent[3 + axis], grid.extent()[1][axis]);
    }
  }
}

TEST_F(GpuTest, BoxGridIsTheCpusOnTheDevice) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<Box> boxes;
    for (int i = 0; i < 3000; ++i) boxes.push_back(random_box(random, 0.6, 0.25));
    if (trial % 2 == 1) {
      for (int i = 0; i < 5; ++i) boxes.push_back(random_box(random, 1.0, 3.0));  // kept aside
    }
    expect_same_grid(device(), boxes);
  }
  expect_same_grid(device(), sheet_boxes(40, 30, false));
  expect_same_grid(device(), sheet_boxes(40, 30, true));
  expect_same_grid(device(), {});
}

}  // namespace
}  // namespace clothsim
