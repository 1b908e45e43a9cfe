// The element force passes on the device: accumulate_connector_springs and
// accumulate_radial_springs, the GPU counterparts of the CPU functions of the same names
// (src/forces/connector_springs.cpp, radial_springs.cpp), evaluating the formulas of
// forces/element_math.inc, the text the CPU compiles too. Each writes one force slot per element
// end (connector e: slots 2e, 2e+1; radial spring r: 3r centre, 3r+1 b, 3r+2 c) and one damping
// power per element, as the CPU's ForceBuffers do.
//
// This class runs one pass on arrays of elements, all of them acting, uploading its arrays and
// reading the result back on each call: what tests/gpu needs to hold the device's element forces
// against element.h on random inputs. The same shaders serve a whole sheet in DeviceForces
// (device_forces.h), with broken springs and the force-term mask.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"

namespace clothsim::gpu {

// The CPU's arrays (ClothModel's names and shapes), read as they are.
struct ConnectorSpringArrays {
  std::span<const Vec3> position;                                     // [particle_count], m
  std::span<const Vec3> velocity;                                     // [particle_count], m/s
  std::span<const std::array<std::uint32_t, 2>> connector_particles;  // [connector_count]: (a, b)
  std::span<const double> connector_rest_length;                      // [connector_count], m
  std::span<const double> connector_stiffness;                        // [connector_count], N/m
  std::span<const double> connector_damping;                          // [connector_count], N s/m
};

struct RadialSpringArrays {
  std::span<const Vec3> position;                                  // [particle_count], m
  std::span<const Vec3> velocity;                                  // [particle_count], m/s
  std::span<const std::array<std::uint32_t, 3>> radial_particles;  // [radial_count]: (centre, b, c)
  std::span<const double> radial_rest_angle;                       // [radial_count], rad
  std::span<const double> radial_stiffness;                        // [radial_count], N m/rad
  std::span<const double> radial_damping;                          // [radial_count], N m s/rad
  std::span<const double> radial_fade_length;  // [2 radial_count]: the b and c arms' (radial_fade_lengths), m
};

// A pass's output, in double whatever the device's precision.
struct ElementForces {
  std::vector<Vec3> slot_force;       // [slots per element x element count], N
  std::vector<double> element_power;  // [element count], W, damping power (never positive)
};

class ElementForcePasses {
 public:
  // Throws GpuError for float64 on a device without shaderFloat64.
  ElementForcePasses(Device& device, Precision precision);

  // damped: the springs' damping acts (the CPU's kSpringDamping term); otherwise elastic forces only.
  ElementForces accumulate_connector_springs(const ConnectorSpringArrays& arrays, bool damped);
  ElementForces accumulate_radial_springs(const RadialSpringArrays& arrays, bool damped);

  Precision precision() const { return precision_; }

 private:
  ElementForces run(ComputePipeline& pipeline, std::span<const std::vector<std::byte>> inputs,
                    std::uint32_t element_count, std::uint32_t slots_per_element, bool damped);

  Device& device_;
  Precision precision_;
  ComputePipeline connector_pass_;
  ComputePipeline radial_pass_;
};

}  // namespace clothsim::gpu
