// Self-collision's candidates on the device (gpu/device_self_candidates.h) against the CPU's
// (SelfContacts::find_candidates): the same pairs in the same order, for a folded sheet falling
// onto itself and the floor (folded_sheet.h), over one short motion and over a long one, with a
// small and a large margin.
#include "gpu/device_self_candidates.h"

#include <gtest/gtest.h>

#include <span>
#include <vector>

#include "collision/self_contacts.h"
#include "collision/sheet_elements.h"
#include "folded_sheet.h"
#include "gpu/real_arrays.h"
#include "gpu_fixture.h"

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
      EXPECT_GT(cpu.candidates().size(), 1000u) << later << " " << margin;
      ASSERT_EQ(found.size(), cpu.candidates().size()) << later << " " << margin;
      EXPECT_TRUE(std::equal(found.begin(), found.end(), cpu.candidates().begin())) << later << " " << margin;
    }
  }
}

}  // namespace
}  // namespace clothsim
