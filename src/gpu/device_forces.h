// The general force path on the device: evaluate_forces (src/forces/forces.h) with
// ForceKernel::general, as passes in one submission:
//   accumulate_connector_springs, accumulate_radial_springs  -> one slot array (the CPU's slots)
//                                                               and the elements' damping powers
//   gather_forces                                            -> each particle sums its slots in
//                                                               the gather table's order, plus
//                                                               gravity and air drag
//   deterministic_sum (two phases)                           -> the damping power, summed over
//                                                               the CPU's fixed blocks in order
// The model's arrays are uploaded once, in the CPU's structure-of-arrays layout (unchanged in
// float64); each evaluate() uploads the state and reads the forces back. That round trip is what
// the backend's step will not do (docs/gpu.md, "Not done yet"): this class is the force function
// it will call on the device, and what tests/gpu holds against the CPU today.
//
// Which elements act is decided when the model is uploaded: live and its term on (the CPU's
// condition), as one flag per element. The model's revision is recorded; a model changed since
// (tearing, plasticity, live edits) must be uploaded again (a CLOTHSIM_ASSERT).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "forces/forces.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "model/cloth_model.h"

namespace clothsim::gpu {

class DeviceForces {
 public:
  // Uploads the model. Throws GpuError when the device lacks the precision or the memory
  // ("the scene needs X MiB of device memory, <device> has Y MiB"), before allocating anything.
  DeviceForces(Device& device, const ClothModel& model, Precision precision, ForceTerms terms);

  // The total force on every particle [particle_count()], as evaluate_forces computes it, and
  // the damping power of the springs (ForcePowers::damping, W). The drag power is not computed
  // on the device yet.
  double evaluate(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                  std::span<Vec3> force);

  // Device memory for a model's arrays, the state and the scratch, bytes.
  static std::uint64_t bytes_for(const ClothModel& model, Precision precision);

 private:
  // The device's arrays, by the CPU's names: the state, the model, the scratch, the results.
  enum Array : std::uint32_t {
    position,
    velocity,
    particle_mass,
    environment,
    gather_offset,
    gather_slot,
    connector_particles,
    connector_rest_length,
    connector_stiffness,
    connector_damping,
    connector_active,
    radial_particles,
    radial_rest_angle,
    radial_stiffness,
    radial_damping,
    radial_active,
    slot_force,
    element_power,
    force,
    block_power,    // the damping power's block sums
    damping_power,  // [1]
    array_count
  };

  Device& device_;
  Precision precision_;
  ForceTerms terms_;
  std::uint64_t model_revision_;
  std::uint32_t particles_, connectors_, radials_;
  std::vector<Buffer> arrays_;  // [array_count]
  ComputePipeline connector_pass_, radial_pass_, gather_pass_, sum_pass_;
};

}  // namespace clothsim::gpu
