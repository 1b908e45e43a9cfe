// The shared laws as the shaders compile them (core/shared_text.h lists the files), through
// shared_laws_probe.comp, against their closed forms and against the CPU's compilation of the
// same text, in both precisions: the arctangent, x / sin x, the event laws, the step-size
// controller and clip_step, and the lattice's spring order. The CPU's sides are held to the same
// closed forms in tests/forces/test_arctangent.cpp, tests/events/test_spring_laws.cpp,
// tests/integrators/test_step_control.cpp and tests/model/test_lattice_springs.cpp.
//
// The bounds: in float64, the arithmetic laws within 4 ulps of the CPU (the same operations; a
// driver may round a division differently), the arctangent within 2 ulps of libm like the CPU's,
// and the controller, whose factors the shader computes in float (rk_control.comp), within float's
// 1e-6. In float32, the inputs are rounded to float and the bounds are float's: 16 float ulps of
// the CPU's double result for the arithmetic laws, 8 of libm's float atan2 for the arctangent.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "events/spring_laws.h"
#include "forces/element.h"
#include "forces/vector_math.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/embedded_shaders.h"
#include "gpu/real_arrays.h"
#include "gpu_fixture.h"
#include "integrators/step_control.h"
#include "model/lattice_springs.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::GpuTest;
using testing::TestRandom;

constexpr double kPi = std::numbers::pi;
constexpr double kEpsilon64 = std::numeric_limits<double>::epsilon();
constexpr double kEpsilon32 = std::numeric_limits<float>::epsilon();
constexpr std::array<gpu::Precision, 2> kPrecisions = {gpu::Precision::float64, gpu::Precision::float32};

// The probe's laws (shared_laws_probe.comp, main).
enum Law : std::uint32_t { arctangent, x_over_sin, stretching, tearing_and_creasing, controller, clipping, order };

using Case = std::array<double, 4>;

// The probe's four outputs of each case, run in `precision` (the inputs rounded to it).
std::vector<Case> probe(gpu::Device& device, gpu::Precision precision, Law law, const std::vector<Case>& cases) {
  device.require_precision(precision);
  std::vector<double> inputs;
  for (const Case& c : cases) inputs.insert(inputs.end(), c.begin(), c.end());
  const std::vector<std::byte> input_bytes = gpu::real_bytes(inputs, precision);
  gpu::Buffer input(device, input_bytes.size(), gpu::Memory::device_local);
  gpu::Buffer output(device, input_bytes.size(), gpu::Memory::device_local);
  gpu::upload(device, input, input_bytes);
  gpu::ComputePipeline pipeline(device, gpu::embedded_shader(gpu::shader_variant("shared_laws_probe", precision)), 2,
                                2 * sizeof(std::uint32_t));
  const std::array<const gpu::Buffer*, 2> bound{&input, &output};
  pipeline.bind(bound);
  const std::array<std::uint32_t, 2> constants{law, static_cast<std::uint32_t>(cases.size())};
  device.submit([&](VkCommandBuffer commands) {
    pipeline.dispatch(commands, constants.data(), static_cast<std::uint32_t>(cases.size()));
  });
  std::vector<std::byte> output_bytes(input_bytes.size());
  gpu::download(device, output, output_bytes);
  const std::vector<double> outputs = gpu::reals_from_bytes(output_bytes, precision);
  std::vector<Case> results(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    for (std::size_t k = 0; k < 4; ++k) results[i][k] = outputs[4 * i + k];
  }
  return results;
}

// `cases` as the device sees them in `precision`.
std::vector<Case> rounded(const std::vector<Case>& cases, gpu::Precision precision) {
  if (precision == gpu::Precision::float64) return cases;
  std::vector<Case> out = cases;
  for (Case& c : out) {
    for (double& value : c) value = static_cast<float>(value);
  }
  return out;
}

// Distance in units in the last place of `exact` (in double or in float).
double ulps(double value, double exact, bool in_float) {
  if (value == exact) return 0.0;
  const double step = in_float ? static_cast<double>(std::nextafter(static_cast<float>(std::abs(exact)), 4.0f) -
                                                     static_cast<float>(std::abs(exact)))
                               : std::nextafter(std::abs(exact), 4.0) - std::abs(exact);
  return std::abs(value - exact) / step;
}

// The bound on the arithmetic laws, relative to the value: 4 ulps in double, 16 float ulps in float.
double relative_bound(gpu::Precision precision) {
  return precision == gpu::Precision::float64 ? 4 * kEpsilon64 : 16 * kEpsilon32;
}

TEST_F(GpuTest, SharedArctangentIsTheCpusWithinLibmsBounds) {
  TestRandom random(53);
  std::vector<Case> cases = {{0, 0, 0, 0}, {0, 1, 0, 0}, {0, -1, 0, 0}, {1, 0, 0, 0}, {1, 1, 0, 0}, {1, -1, 0, 0}};
  for (int i = 0; i < 4000; ++i) {
    const double y = std::pow(10.0, random.uniform(-12, 3));
    const double x = (random.uniform(0, 1) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, random.uniform(-12, 3));
    cases.push_back({y, x, 0, 0});
  }
  for (gpu::Precision precision : kPrecisions) {
    const bool in_float = precision == gpu::Precision::float32;
    const std::vector<Case> inputs = rounded(cases, precision);
    const std::vector<Case> results = probe(device(), precision, arctangent, cases);
    double worst_libm = 0.0;
    double worst_cpu = 0.0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const auto [y, x, unused_c, unused_d] = inputs[i];
      double exact = std::atan2(y, x);
      double cpu = vector_math::atan2_upper_half(y, x);
      if (in_float) {
        exact = std::atan2(static_cast<float>(y), static_cast<float>(x));
        cpu = vector_math::atan2_upper_half(static_cast<float>(y), static_cast<float>(x));
      }
      worst_libm = std::max(worst_libm, ulps(results[i][0], exact, in_float));
      worst_cpu = std::max(worst_cpu, ulps(results[i][0], cpu, in_float));
      if (x != 0.0 || y != 0.0) {
        const double quadrant =
            in_float ? vector_math::atan2_first_quadrant(static_cast<float>(y), std::abs(static_cast<float>(x)))
                     : vector_math::atan2_first_quadrant(y, std::abs(x));
        worst_cpu = std::max(worst_cpu, ulps(results[i][1], quadrant, in_float));
      }
    }
    std::printf("shared arctangent, %s: %.2f ulps from libm, %.2f from the CPU's\n", to_string(precision), worst_libm,
                worst_cpu);
    EXPECT_LE(worst_libm, in_float ? 8.0 : 2.0) << to_string(precision);
    // Exact where the answer is representable: 0, pi, pi/2, pi/4 rounded to the precision.
    EXPECT_EQ(results[0][0], 0.0);
    EXPECT_EQ(results[1][0], 0.0);
    EXPECT_EQ(results[2][0], in_float ? static_cast<double>(std::numbers::pi_v<float>) : kPi);
    EXPECT_EQ(results[3][0], in_float ? static_cast<double>(std::numbers::pi_v<float> / 2) : kPi / 2);
    EXPECT_EQ(results[4][0], in_float ? static_cast<double>(std::numbers::pi_v<float> / 4) : kPi / 4);
  }
}

TEST_F(GpuTest, SharedXOverSinIsTheClosedForm) {
  std::vector<Case> cases;
  for (const double x : {0.0, 1e-9, 1e-6, 5e-5, 9.9e-5, 1.01e-4, 1e-3, 0.1, 0.7, 1.5}) {
    cases.push_back({x, std::sin(x), 0, 0});
  }
  for (gpu::Precision precision : kPrecisions) {
    const std::vector<Case> inputs = rounded(cases, precision);
    const std::vector<Case> results = probe(device(), precision, x_over_sin, cases);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const auto [x, sine, unused_c, unused_d] = inputs[i];
      const double closed = x == 0.0 ? 1.0 : x / sine;
      EXPECT_NEAR(results[i][0], closed, 2 * relative_bound(precision)) << x;
      EXPECT_NEAR(results[i][0], element::x_over_sin(x, sine), relative_bound(precision)) << x;
    }
  }
}

TEST_F(GpuTest, SharedEventLawsAreTheCpus) {
  // Stretching: (length, rest, yield, hardening) pulled, pushed, within, refused.
  const std::vector<Case> stretch = {{1.1, 1.0, 0.02, 0.0},
                                     {1.1, 1.0, 0.02, 0.5},
                                     {0.9, 1.0, 0.02, 0.25},
                                     {1.01, 1.0, 0.02, 0.5},
                                     {0.1, 1.0, 1.5, 0.0}};
  // Tearing (length, original, break strain) and creasing (angle, rest angle, yield angle) on the
  // same three numbers.
  const std::vector<Case> tear_crease = {
      {1.1, 1.0, 0.2, 0}, {1.3, 1.0, 0.2, 0}, {2.5, 1.5, 0.1, 0}, {0.5, 1.0, 0.2, 0},
      {kPi, 0.5, 0.2, 0}, {0.0, 2.0, 0.5, 0}, {1.2, 1.0, 0.3, 0}, {kPi / 2 + 0.5, kPi / 2, 0.1, 0}};
  for (gpu::Precision precision : kPrecisions) {
    const double bound = relative_bound(precision);
    const std::vector<Case> inputs = rounded(stretch, precision);
    const std::vector<Case> results = probe(device(), precision, stretching, stretch);
    for (std::size_t i = 0; i < stretch.size(); ++i) {
      const auto [length, rest, yield, hardening] = inputs[i];
      const spring_laws::ReturnMapping cpu = spring_laws::return_mapping(length, rest, yield, hardening);
      EXPECT_EQ(results[i][0] != 0.0, cpu.yields) << i;
      EXPECT_EQ(results[i][3] != 0.0, spring_laws::connector_yields(length, rest, yield)) << i;
      EXPECT_NEAR(results[i][1], cpu.rest_length, bound * cpu.rest_length) << i;
      EXPECT_NEAR(results[i][2], cpu.yield_strain, bound * cpu.yield_strain) << i;
      if (cpu.yields) {
        // The closed form: the elastic strain left is the old yield strain.
        const double sign = length > rest ? 1.0 : -1.0;
        EXPECT_NEAR(results[i][1], length / (1.0 + sign * yield), 2 * bound * rest) << i;
      }
    }
    const std::vector<Case> tc_inputs = rounded(tear_crease, precision);
    const std::vector<Case> tc = probe(device(), precision, tearing_and_creasing, tear_crease);
    for (std::size_t i = 0; i < tear_crease.size(); ++i) {
      const auto [a, b, c, unused] = tc_inputs[i];
      EXPECT_EQ(tc[i][0] != 0.0, spring_laws::connector_breaks(a, b, c)) << i;
      EXPECT_NEAR(tc[i][1], spring_laws::creased_rest_angle(a, b, c), 4 * bound) << i;
    }
    // The closed forms of the crease law: theta - sign(theta - theta0) a.
    EXPECT_NEAR(tc[7][1], kPi / 2 + 0.4, 4 * bound);
    EXPECT_NEAR(tc[4][1], kPi - 0.2, 4 * bound);
    EXPECT_EQ(tc[5][1], 0.5);
    EXPECT_EQ(tc[6][1], 1.0);  // within the yield: unchanged
  }
}

TEST_F(GpuTest, SharedStepControllerIsTheCpus) {
  // (step, error, previous error, 1 rejected before + 2 clipped); error > 1 rejects.
  const std::vector<Case> cases = {{1e-3, 0.3, 0.5, 0},  {1e-3, 0.0, 0.3, 0},  {1e-3, 1e-6, 1e-4, 1},
                                   {1e-4, 0.9, 1e-4, 2}, {1e-3, 2.0, 1e-4, 0}, {1e-3, 1e12, 1e-4, 0},
                                   {2e-5, 0.7, 0.02, 3}, {1e-2, 1.0, 1e-4, 0}};
  const std::vector<Case> clip_cases = {
      {0.0, 0.1, 1.0, 0}, {0.5, 0.7, 1.0, 0}, {0.0, 1.0 - 1e-7, 1.0, 0}, {0.0, 1.0 - 1e-5, 1.0, 0}};
  for (gpu::Precision precision : kPrecisions) {
    const std::vector<Case> inputs = rounded(cases, precision);
    const std::vector<Case> results = probe(device(), precision, controller, cases);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const auto [step, error, previous, flags] = inputs[i];
      step_control::StepController cpu = step_control::make_step_controller(IntegratorSettings{});
      cpu.proposed_step = step;
      cpu.previous_error = previous;
      cpu.rejected_before = (static_cast<int>(flags) & 1) != 0;
      if (error > 1.0) {
        step_control::reject_step(cpu, step, error, false);
      } else {
        step_control::accept_step(cpu, step, error, (static_cast<int>(flags) & 2) != 0);
      }
      // The factors are float on the device: float's relative rounding, a few times over.
      EXPECT_NEAR(results[i][0], cpu.proposed_step, 1e-6 * cpu.proposed_step) << i;
      EXPECT_NEAR(results[i][1], cpu.previous_error, relative_bound(precision) * cpu.previous_error) << i;
      EXPECT_EQ(results[i][2] != 0.0, cpu.rejected_before) << i;
    }
    // The closed forms: the PI factor, growth capped at 5 and at 1 after a rejection, a clipped
    // step keeping the old proposal, the rejection's factor floored at max_shrink.
    const double alpha = 0.2 - 0.75 * 0.04;
    EXPECT_NEAR(results[0][0], 1e-3 * 0.9 * std::pow(0.3, -alpha) * std::pow(0.5, 0.04), 1e-9);
    EXPECT_NEAR(results[1][0], 5e-3, 1e-9);
    EXPECT_NEAR(results[2][0], 1e-3, 1e-9);
    EXPECT_NEAR(results[3][0], 1e-4, 1e-10);
    EXPECT_NEAR(results[4][0], 1e-3 * 0.9 * std::pow(2.0, -0.2), 1e-9);
    EXPECT_NEAR(results[5][0], 1e-4, 1e-10);

    const std::vector<Case> clipped = probe(device(), precision, clipping, clip_cases);
    const std::vector<Case> clip_inputs = rounded(clip_cases, precision);
    for (std::size_t i = 0; i < clip_cases.size(); ++i) {
      const auto [time, step, limit, unused] = clip_inputs[i];
      const step_control::ClippedStep cpu = step_control::clip_step(time, step, limit);
      EXPECT_EQ(clipped[i][1] != 0.0, cpu.clipped) << i;
      EXPECT_EQ(clipped[i][0], cpu.step) << i;
    }
    EXPECT_EQ(clipped[2][0], 1.0);  // stretched to the limit
  }
}

TEST_F(GpuTest, SharedSpringOrderIsTheModels) {
  const std::vector<Case> cases(12, Case{});
  for (gpu::Precision precision : kPrecisions) {
    const std::vector<Case> results = probe(device(), precision, order, cases);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      EXPECT_EQ(results[i][0], kRadialArmB[i % 6]) << i;
      EXPECT_EQ(results[i][1], kRadialArmC[i % 6]) << i;
    }
  }
}

}  // namespace
}  // namespace clothsim
