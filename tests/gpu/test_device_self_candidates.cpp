// Self-collision's candidates on the device (gpu/device_self_candidates.h) against the CPU's
// (SelfContacts::find_candidates): the same pairs in the same order, for a folded sheet falling
// onto itself and the floor (folded_sheet.h), over one short motion and over a long one, with a
// small and a large margin, and pruned; and stages 2 and 3's tests on them against the CPU's shared
// text.
#include "gpu/device_self_candidates.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "collision/self_contacts.h"
#include "collision/self_pair.h"
#include "collision/sheet_elements.h"
#include "folded_sheet.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/self_step.h"
#include "gpu_fixture.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

using testing::GpuTest;

gpu::Buffer position_buffer(gpu::Device& device, std::span<const Vec3> x) {
  std::vector<double> reals;
  for (const Vec3& p : x) reals.insert(reals.end(), {p.x, p.y, p.z});
  const std::vector<std::byte> bytes = gpu::real_bytes(reals, gpu::Precision::float64);
  gpu::Buffer buffer(device, bytes.size(), gpu::Memory::device_local);
  gpu::upload(device, buffer, bytes);
  return buffer;
}

// The last find()'s candidates as the CPU lists them (SelfContacts::candidates).
std::vector<SelfPair> found_pairs(const gpu::DeviceSelfCandidates& on_device, const SheetElements& elements) {
  std::vector<SelfPair> found;
  const std::vector<std::uint32_t> points = on_device.point_triangle_pairs();
  for (std::size_t k = 0; k + 1 < points.size(); k += 2) {
    const auto& t = elements.triangle[points[k + 1]];
    found.push_back({{points[k], t[0], t[1], t[2]}, {points[k], points[k + 1]}, SelfPair::Kind::point_triangle});
  }
  const std::vector<std::uint32_t> edges = on_device.edge_pairs();
  for (std::size_t k = 0; k + 1 < edges.size(); k += 2) {
    const auto& e = elements.edge[edges[k]];
    const auto& f = elements.edge[edges[k + 1]];
    found.push_back({{e[0], e[1], f[0], f[1]}, {edges[k], edges[k + 1]}, SelfPair::Kind::edge_edge});
  }
  return found;
}

TEST_F(GpuTest, SelfCandidatesAreTheCpusInTheCpusOrder) {
  Simulation simulation = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1);
  ASSERT_TRUE(simulation.advance_to(0.03)) << simulation.failure()->message;
  const std::vector<Vec3> start = simulation.state().position;
  for (const double later : {0.031, 0.06}) {
    ASSERT_TRUE(simulation.advance_to(later)) << simulation.failure()->message;
    const std::vector<Vec3>& end = simulation.state().position;
    const ClothModel& model = simulation.model();
    SheetElements elements;
    refresh_sheet_elements(model, elements);
    const gpu::Buffer start_buffer = position_buffer(device(), start);
    const gpu::Buffer end_buffer = position_buffer(device(), end);
    gpu::DeviceSelfCandidates on_device(device(), gpu::Precision::float64,
                                        static_cast<std::uint32_t>(model.particle_count()), elements);
    for (const double margin : {0.006, 0.03}) {
      SelfContacts cpu;
      cpu.find_candidates(model, start, end, margin, 1);
      on_device.find(start_buffer, end_buffer, margin);
      const std::vector<SelfPair> found = found_pairs(on_device, elements);
      EXPECT_GT(cpu.candidates().size(), 1000u) << later << " " << margin;
      ASSERT_EQ(found.size(), cpu.candidates().size()) << later << " " << margin;
      EXPECT_TRUE(std::equal(found.begin(), found.end(), cpu.candidates().begin())) << later << " " << margin;
      // Pruned at the end positions as the CPU prunes (SelfContacts::prune_blocks): the pairs nearer
      // than the reach, in their order, as two words each (shaders/self_step.h).
      constexpr double reach = 0.01;  // the layers are 4 to 6 mm apart
      std::vector<std::uint32_t> kept;
      for (const SelfPair& pair : cpu.candidates()) {
        const std::array<Vec3, 4> corners{end[pair.particle[0]], end[pair.particle[1]], end[pair.particle[2]],
                                          end[pair.particle[3]]};
        if (measure_pair(pair.kind, corners).distance >= reach) continue;
        const bool point = pair.kind == SelfPair::Kind::point_triangle;
        kept.insert(kept.end(), {pair.element[0] | (point ? 0u : gpu::kEdgePairBit), pair.element[1]});
      }
      EXPECT_EQ(on_device.pairs().size(), found.size() * 2) << "find keeps them all";
      on_device.prune(end_buffer, reach);
      EXPECT_GT(kept.size(), 200u);
      EXPECT_LT(kept.size() / 2, found.size()) << "some are dropped";
      EXPECT_EQ(on_device.pairs(), kept) << later << " " << margin;
    }
  }
}

// A sheet torn after its candidates' search was made: the search takes the torn sheet's triangles
// and edges in place (DeviceSelfContacts::refresh, at a tear) and finds the CPU's candidates of the
// torn sheet; more elements than it was made for it refuses, changing nothing.
TEST_F(GpuTest, SelfCandidatesTakeATornSheetsElementsInPlace) {
  Simulation simulation = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1);
  ASSERT_TRUE(simulation.advance_to(0.03)) << simulation.failure()->message;
  const std::vector<Vec3> start = simulation.state().position;
  ASSERT_TRUE(simulation.advance_to(0.06)) << simulation.failure()->message;
  const std::vector<Vec3> end = simulation.state().position;
  ClothModel torn = simulation.model();
  SheetElements intact;
  refresh_sheet_elements(torn, intact);
  const auto particles = static_cast<std::uint32_t>(torn.particle_count());
  gpu::DeviceSelfCandidates on_device(device(), gpu::Precision::float64, particles, intact);
  for (std::uint32_t c = 0; c < torn.connector_count(); c += 7) break_connector(torn, c);
  SheetElements elements;
  refresh_sheet_elements(torn, elements);
  ASSERT_LT(elements.triangle.size(), intact.triangle.size());
  ASSERT_LT(elements.edge.size(), intact.edge.size());
  ASSERT_TRUE(on_device.set_elements(elements));
  constexpr double margin = 0.03;
  SelfContacts cpu;
  cpu.find_candidates(torn, start, end, margin, 1);
  on_device.find(position_buffer(device(), start), position_buffer(device(), end), margin);
  EXPECT_GT(cpu.candidates().size(), 1000u);
  const std::vector<SelfPair> found = found_pairs(on_device, elements);
  ASSERT_EQ(found.size(), cpu.candidates().size());
  EXPECT_TRUE(std::equal(found.begin(), found.end(), cpu.candidates().begin()));
  gpu::DeviceSelfCandidates made_torn(device(), gpu::Precision::float64, particles, elements);
  EXPECT_FALSE(made_torn.set_elements(intact));
}

struct DetectionCounts {
  std::size_t active = 0, near = 0, touching = 0;
};

// Stages 2 and 3's tests on the device over the motion start -> end of `model`'s sheet, against the
// CPU's shared text (collision/self_pair.h): every pair near is active; of the active ones, the
// distance at the start within 4 ulps of the CPU's, near and touching as the CPU decides.
DetectionCounts expect_detection_is_the_cpus(gpu::Device& device, const ClothModel& model,
                                             const std::vector<Vec3>& start, const std::vector<Vec3>& end,
                                             double thickness) {
  SheetElements elements;
  refresh_sheet_elements(model, elements);
  const gpu::Buffer start_buffer = position_buffer(device, start);
  const gpu::Buffer end_buffer = position_buffer(device, end);
  gpu::DeviceSelfCandidates on_device(device, gpu::Precision::float64,
                                      static_cast<std::uint32_t>(model.particle_count()), elements);
  constexpr double kMargin = 0.03;
  on_device.find(start_buffer, end_buffer, kMargin);
  on_device.detect(start_buffer, end_buffer, thickness);
  SelfContacts cpu;
  cpu.find_candidates(model, start, end, kMargin, 1);
  const std::vector<std::uint32_t> flags = on_device.flags();
  const std::vector<double> distances = on_device.start_distances();
  EXPECT_EQ(flags.size(), cpu.candidates().size());
  DetectionCounts counts;
  for (std::size_t k = 0; k < std::min(flags.size(), cpu.candidates().size()); ++k) {
    const SelfPair& pair = cpu.candidates()[k];
    const auto corners = [&](const std::vector<Vec3>& x) {
      return self_pair::PairCorners{
          {x[pair.particle[0]], x[pair.particle[1]], x[pair.particle[2]], x[pair.particle[3]]}};
    };
    const int kind =
        pair.kind == SelfPair::Kind::point_triangle ? self_pair::kPairPointTriangle : self_pair::kPairEdgeEdge;
    const double d0 = self_pair::measure_pair_corners(kind, corners(start)).distance;
    const double d1 = self_pair::measure_pair_corners(kind, corners(end)).distance;
    const bool near = (d0 < thickness || d1 < thickness) && d0 != 0.0;
    const bool active = (flags[k] & gpu::kPairActive) != 0;
    EXPECT_TRUE(active || !near) << k;
    if (!active) {
      EXPECT_EQ(flags[k], 0u) << k;
      continue;
    }
    ++counts.active;
    EXPECT_LE(std::abs(distances[k] - d0), 4 * std::numeric_limits<double>::epsilon() * d0) << k;
    EXPECT_EQ((flags[k] & gpu::kPairNear) != 0, near) << k;
    const bool touches = self_pair::first_touch(kind, corners(start), corners(end), thickness, d0) >= 0.0;
    EXPECT_EQ((flags[k] & gpu::kPairTouching) != 0, touches) << k;
    counts.near += near ? 1 : 0;
    counts.touching += touches ? 1 : 0;
  }
  return counts;
}

TEST_F(GpuTest, SelfDetectionIsTheCpusOnTheCandidates) {
  // The folded sheet over a step: with a thickness of 8 mm its layers, 6 mm apart, are near; moved
  // 12 mm down, its upper layer passes through the lower one, and pairs touch.
  Simulation simulation = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, 1);
  ASSERT_TRUE(simulation.advance_to(0.02)) << simulation.failure()->message;
  const std::vector<Vec3> start = simulation.state().position;
  ASSERT_TRUE(simulation.advance_to(0.03)) << simulation.failure()->message;
  std::vector<Vec3> end = simulation.state().position;
  const DetectionCounts near = expect_detection_is_the_cpus(device(), simulation.model(), start, end, 0.008);
  EXPECT_GT(near.active, 100u);
  EXPECT_GT(near.near, 50u);
  for (std::size_t p = 8 * 16; p < end.size(); ++p) end[p].y -= 0.012;
  const DetectionCounts through = expect_detection_is_the_cpus(device(), simulation.model(), start, end, 0.008);
  EXPECT_GT(through.touching, 50u);
}

}  // namespace
}  // namespace clothsim
