// Self-collision's pair geometry (collision/self_pair.inc, shared text) as the shaders compile it,
// through self_pair_probe.comp, against the CPU's compilation of the same text (the self pass,
// collision/self_contacts.h) and against brute force: a particle and a triangle, two edges, each
// at random and in the degenerate cases (a triangle that is a segment or a point, parallel edges,
// an edge that is a point), still, translated rigidly, and passing through each other. In float64:
// the distances, normals, weights and the distance's rate bound within 4 ulps of the CPU's (the
// same operations; a driver may round a division or a square root differently), the first touch
// within 1e-12 of the CPU's (tests/collision/test_self_pair.cpp holds the CPU's to brute force).
// The pairs: tests/collision/self_pair_cases.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "collision/self_contacts.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/embedded_shaders.h"
#include "gpu/real_arrays.h"
#include "gpu_fixture.h"
#include "self_pair_cases.h"

namespace clothsim {
namespace {

using testing::corners;
using testing::GpuTest;
using testing::kind_of;
using testing::kPairThickness;
using testing::PairCase;
namespace shared = testing::shared;

constexpr std::uint32_t kInputs = 26;  // self_pair_probe.comp's
constexpr std::uint32_t kOutputs = 11;

struct PairResult {
  double distance = 0.0;
  Vec3 normal;
  std::array<double, 4> weight{};
  double bound = 0.0;
  double touch = 0.0;  // the first touch, -1 for none
  double end_distance = 0.0;
};

std::vector<PairResult> on_device(gpu::Device& device, const std::vector<PairCase>& cases) {
  const gpu::Precision precision = gpu::Precision::float64;
  device.require_precision(precision);
  std::vector<double> inputs;
  for (const PairCase& c : cases) {
    inputs.push_back(kind_of(c.kind));
    inputs.push_back(kPairThickness);
    for (const auto* corners : {&c.start, &c.end}) {
      for (const Vec3& x : *corners) inputs.insert(inputs.end(), {x.x, x.y, x.z});
    }
  }
  EXPECT_EQ(inputs.size(), kInputs * cases.size());
  const std::vector<std::byte> input_bytes = gpu::real_bytes(inputs, precision);
  gpu::Buffer input(device, input_bytes.size(), gpu::Memory::device_local);
  gpu::Buffer output(device, std::uint64_t{kOutputs} * cases.size() * sizeof(double), gpu::Memory::device_local);
  gpu::upload(device, input, input_bytes);
  gpu::ComputePipeline pipeline(device, gpu::embedded_shader(gpu::shader_variant("self_pair_probe", precision)), 2,
                                sizeof(std::uint32_t));
  const std::array<const gpu::Buffer*, 2> bound{&input, &output};
  pipeline.bind(bound);
  const auto count = static_cast<std::uint32_t>(cases.size());
  device.submit([&](VkCommandBuffer commands) { pipeline.dispatch(commands, &count, count); });
  std::vector<std::byte> output_bytes(output.bytes());
  gpu::download(device, output, output_bytes);
  const std::vector<double> out = gpu::reals_from_bytes(output_bytes, precision);
  std::vector<PairResult> results(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const double* r = &out[kOutputs * i];
    results[i] = {r[0], {r[1], r[2], r[3]}, {r[4], r[5], r[6], r[7]}, r[8], r[9], r[10]};
  }
  return results;
}

PairResult on_cpu(const PairCase& c) {
  const PairGeometry geometry = measure_pair(c.kind, c.start);  // the self pass's own
  const int kind = kind_of(c.kind);
  return {geometry.distance,
          geometry.normal,
          geometry.weight,
          shared::pair_motion_bound(kind, corners(c.start), corners(c.end)),
          shared::first_touch(kind, corners(c.start), corners(c.end), kPairThickness, geometry.distance),
          measure_pair(c.kind, c.end).distance};
}

bool within_ulps(double value, double expected, double ulps) {
  return std::abs(value - expected) <= ulps * std::numeric_limits<double>::epsilon() * std::abs(expected);
}

TEST_F(GpuTest, SelfPairGeometryIsTheCpusOnTheDevice) {
  const std::vector<PairCase> cases = testing::random_pair_cases(6000);
  const std::vector<PairResult> device_results = on_device(device(), cases);
  int touching = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const PairResult cpu = on_cpu(cases[i]);
    const PairResult& gpu = device_results[i];
    ASSERT_TRUE(within_ulps(gpu.distance, cpu.distance, 4)) << i << ": " << gpu.distance << " " << cpu.distance;
    ASSERT_TRUE(within_ulps(gpu.end_distance, cpu.end_distance, 4)) << i;
    ASSERT_TRUE(within_ulps(gpu.bound, cpu.bound, 4)) << i;
    for (int k = 0; k < 4; ++k) ASSERT_NEAR(gpu.weight[k], cpu.weight[k], 1e-14) << i << " weight " << k;
    if (cpu.distance > 1e-9) {
      ASSERT_LT(norm(gpu.normal - cpu.normal), 1e-14) << i;
    }
    ASSERT_EQ(gpu.touch < 0.0, cpu.touch < 0.0) << i;
    ASSERT_NEAR(gpu.touch, cpu.touch, 1e-12) << i;
    if (cpu.touch >= 0.0) ++touching;
  }
  EXPECT_GT(touching, 1000);  // the mirrored motions, and some of the random ones
}

}  // namespace
}  // namespace clothsim
