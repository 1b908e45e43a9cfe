// The device's hashed grid of boxes (gpu/device_box_grid.h) against the CPU's BoxGrid
// (collision/box_grid.h), given the CPU's cell size: the same buckets, each holding the same
// entries (cell, box, lowest-cell bits) in the same order, the same boxes kept aside and the same
// extent. Random boxes, with and without a few far larger than the rest; a lattice sheet's
// triangles, flat and folded; no boxes.
#include "gpu/device_box_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <span>
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

// A rows x cols sheet of 1 cm cells, folded about its middle column when `folded` (the folded half
// 4 mm above the other): its particles and triangles.
struct Sheet {
  std::vector<Vec3> position;
  std::vector<std::array<std::uint32_t, 3>> triangle;
};
Sheet sheet(int rows, int cols, bool folded) {
  Sheet out;
  const double fold = 0.01 * (cols / 2);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const double x = 0.01 * j;
      out.position.push_back(folded && x > fold ? Vec3{2 * fold - x, 0.004, 0.01 * i} : Vec3{x, 0.0, 0.01 * i});
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * cols + j); };
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j + 1 < cols; ++j) {
      out.triangle.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
      out.triangle.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return out;
}

Box grown(Box box, double margin) {
  return {box.low - Vec3{margin, margin, margin}, box.high + Vec3{margin, margin, margin}};
}

std::vector<Box> triangle_boxes(const Sheet& s, double margin) {
  std::vector<Box> boxes;
  for (const auto& t : s.triangle) {
    Box box{s.position[t[0]], s.position[t[0]]};
    for (const std::uint32_t p : t) {
      const Vec3& c = s.position[p];
      box.low = {std::min(box.low.x, c.x), std::min(box.low.y, c.y), std::min(box.low.z, c.z)};
      box.high = {std::max(box.high.x, c.x), std::max(box.high.y, c.y), std::max(box.high.z, c.z)};
    }
    boxes.push_back(grown(box, margin));
  }
  return boxes;
}

std::vector<Box> sheet_boxes(int rows, int cols, bool folded) {
  return triangle_boxes(sheet(rows, cols, folded), 0.002);
}

gpu::Buffer box_buffer(gpu::Device& device, const std::vector<Box>& boxes) {
  std::vector<double> reals;
  for (const Box& b : boxes) reals.insert(reals.end(), {b.low.x, b.low.y, b.low.z, b.high.x, b.high.y, b.high.z});
  if (reals.empty()) reals.push_back(0.0);
  const std::vector<std::byte> bytes = gpu::real_bytes(reals, gpu::Precision::float64);
  gpu::Buffer buffer(device, bytes.size(), gpu::Memory::device_local);
  gpu::upload(device, buffer, bytes);
  return buffer;
}

void expect_same_grid(gpu::Device& device, const std::vector<Box>& boxes) {
  BoxGrid grid;
  grid.build(boxes);
  const gpu::Buffer buffer = box_buffer(device, boxes);
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

// The pairs the CPU's grid finds for `queries` in turn, skipping a box whose `corners` name the query.
std::vector<std::uint32_t> cpu_pairs(const BoxGrid& grid, const std::vector<Box>& queries,
                                     const std::vector<std::array<std::uint32_t, 3>>* corners) {
  std::vector<std::uint32_t> pairs;
  for (std::uint32_t q = 0; q < queries.size(); ++q) {
    grid.for_each_overlap(queries[q], [&](std::uint32_t b) {
      if (corners != nullptr && ((*corners)[b][0] == q || (*corners)[b][1] == q || (*corners)[b][2] == q)) return;
      pairs.insert(pairs.end(), {q, b});
    });
  }
  return pairs;
}

TEST_F(GpuTest, BoxGridQueriesFindTheCpusPairsInItsOrder) {
  // Self-collision's particles against the triangles (boxes grown by 3 mm, a particle's own
  // triangles skipped) on a sheet flat and folded, its particles moving; random boxes, some kept
  // aside, against random queries.
  for (const bool folded : {false, true}) {
    Sheet start = sheet(40, 30, folded);
    Sheet end = start;
    for (std::size_t p = 0; p < end.position.size(); ++p) end.position[p] += Vec3{0.0, 0.001 * double(p % 3), 0.0};
    std::vector<Box> particle_boxes;
    for (std::size_t p = 0; p < start.position.size(); ++p) {
      const Vec3& a = start.position[p];
      const Vec3& b = end.position[p];
      particle_boxes.push_back(grown({{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)},
                                      {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}},
                                     0.003));
    }
    const std::vector<Box> triangles = triangle_boxes(end, 0.003);
    BoxGrid grid;
    grid.build(triangles);
    const std::vector<std::uint32_t> expected = cpu_pairs(grid, particle_boxes, &end.triangle);
    const gpu::Buffer stored = box_buffer(device(), triangles);
    const gpu::Buffer queries = box_buffer(device(), particle_boxes);
    std::vector<std::uint32_t> corner_words;
    for (const auto& t : end.triangle) corner_words.insert(corner_words.end(), t.begin(), t.end());
    gpu::Buffer corners(device(), corner_words.size() * sizeof(std::uint32_t), gpu::Memory::device_local);
    gpu::upload(device(), corners, std::as_bytes(std::span(corner_words)));
    gpu::DeviceBoxGrid on_device(device(), gpu::Precision::float64, static_cast<std::uint32_t>(triangles.size()));
    on_device.build(stored, static_cast<std::uint32_t>(triangles.size()), grid.cell_size());
    gpu::DeviceGridQuery query(device(), gpu::Precision::float64, static_cast<std::uint32_t>(particle_boxes.size()));
    EXPECT_EQ(query.run(on_device, stored, queries, static_cast<std::uint32_t>(particle_boxes.size()), &corners),
              expected.size() / 2);
    EXPECT_GT(expected.size(), folded ? 10'000u : 2'000u);
    EXPECT_EQ(query.pairs(), expected) << "folded " << folded;
  }
  std::mt19937 random(3);
  std::vector<Box> boxes;
  std::vector<Box> queries;
  for (int i = 0; i < 2000; ++i) boxes.push_back(random_box(random, 0.6, 0.25));
  for (int i = 0; i < 4; ++i) boxes.push_back(random_box(random, 1.0, 3.0));  // kept aside
  for (int i = 0; i < 1500; ++i) queries.push_back(random_box(random, 0.7, 0.3));
  BoxGrid grid;
  grid.build(boxes);
  const gpu::Buffer stored = box_buffer(device(), boxes);
  const gpu::Buffer query_boxes = box_buffer(device(), queries);
  gpu::DeviceBoxGrid on_device(device(), gpu::Precision::float64, static_cast<std::uint32_t>(boxes.size()));
  on_device.build(stored, static_cast<std::uint32_t>(boxes.size()), grid.cell_size());
  gpu::DeviceGridQuery query(device(), gpu::Precision::float64, static_cast<std::uint32_t>(queries.size()));
  query.run(on_device, stored, query_boxes, static_cast<std::uint32_t>(queries.size()), nullptr);
  EXPECT_GT(grid.oversize().size(), 0u);
  EXPECT_EQ(query.pairs(), cpu_pairs(grid, queries, nullptr));
}

TEST_F(GpuTest, BoxGridJoinFindsTheCpusPairsInItsOrder) {
  // Self-collision's edges against each other (two with a particle in common skipped) on a sheet
  // flat and folded; random boxes, some kept aside, with none skipped.
  for (const bool folded : {false, true}) {
    const Sheet s = sheet(40, 30, folded);
    std::vector<std::array<std::uint32_t, 2>> edges;
    for (const auto& t : s.triangle) {
      edges.push_back({t[0], t[1]});
      edges.push_back({t[1], t[2]});
    }
    std::vector<Box> boxes;
    for (const auto& e : edges) {
      const Vec3& a = s.position[e[0]];
      const Vec3& b = s.position[e[1]];
      boxes.push_back(grown({{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)},
                             {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}},
                            0.003));
    }
    BoxGrid grid;
    grid.build(boxes);
    std::vector<std::uint32_t> expected;
    grid.for_each_pair(0, grid.bucket_count(), [&](std::uint32_t e, std::uint32_t f) {
      const auto& x = edges[e];
      const auto& y = edges[f];
      if (x[0] == y[0] || x[0] == y[1] || x[1] == y[0] || x[1] == y[1]) return;
      expected.insert(expected.end(), {e, f});
    });
    const gpu::Buffer stored = box_buffer(device(), boxes);
    std::vector<std::uint32_t> edge_words;
    for (const auto& e : edges) edge_words.insert(edge_words.end(), e.begin(), e.end());
    gpu::Buffer particles(device(), edge_words.size() * sizeof(std::uint32_t), gpu::Memory::device_local);
    gpu::upload(device(), particles, std::as_bytes(std::span(edge_words)));
    gpu::DeviceBoxGrid on_device(device(), gpu::Precision::float64, static_cast<std::uint32_t>(boxes.size()));
    on_device.build(stored, static_cast<std::uint32_t>(boxes.size()), grid.cell_size());
    gpu::DeviceGridQuery query(device(), gpu::Precision::float64, 1);
    EXPECT_EQ(query.join(on_device, stored, static_cast<std::uint32_t>(boxes.size()), &particles), expected.size() / 2);
    EXPECT_GT(expected.size(), folded ? 10'000u : 2'000u);
    EXPECT_EQ(query.pairs(), expected) << "folded " << folded;
  }
  std::mt19937 random(5);
  std::vector<Box> boxes;
  for (int i = 0; i < 2500; ++i) boxes.push_back(random_box(random, 0.6, 0.25));
  for (int i = 0; i < 4; ++i) boxes.push_back(random_box(random, 1.0, 3.0));  // kept aside
  BoxGrid grid;
  grid.build(boxes);
  std::vector<std::uint32_t> expected;
  grid.for_each_pair(0, grid.bucket_count(), [&](std::uint32_t i, std::uint32_t j) {
    expected.insert(expected.end(), {i, j});
  });
  const gpu::Buffer stored = box_buffer(device(), boxes);
  gpu::DeviceBoxGrid on_device(device(), gpu::Precision::float64, static_cast<std::uint32_t>(boxes.size()));
  on_device.build(stored, static_cast<std::uint32_t>(boxes.size()), grid.cell_size());
  gpu::DeviceGridQuery query(device(), gpu::Precision::float64, 1);
  query.join(on_device, stored, static_cast<std::uint32_t>(boxes.size()), nullptr);
  EXPECT_GT(grid.oversize().size(), 0u);
  EXPECT_EQ(query.pairs(), expected);
}

}  // namespace
}  // namespace clothsim
