// The general force path on the device: evaluate_forces (src/forces/forces.h) with
// ForceKernel::general, as passes in one submission:
//   accumulate_connector_springs, accumulate_radial_springs  -> one slot array (the CPU's slots)
//                                                               and the elements' damping powers
//   gather_forces                                            -> each particle sums its slots in
//                                                               the gather table's order, plus
//                                                               gravity and air drag
//   deterministic_sum (two phases)                           -> the damping power, summed over
//                                                               the CPU's fixed blocks in order
// The model's arrays are uploaded in the CPU's structure-of-arrays layout (unchanged in float64).
// evaluate() uploads a state and reads the forces back: what tests/gpu holds against the CPU.
// The device step (device_integrator.h) keeps its state on the device instead: it writes each
// stage's state into this class's `position` and `velocity` arrays, records the element passes
// into its own command buffers (record_element_passes), and gathers the slots itself. In float32
// the stage arrays hold offsets from the step's start, which the element passes then read from
// the step's own state arrays (read_origin_from; gpu/shaders/stage_offsets.glsl).
//
// The lattice path of the device step (lattice_elements, device_integrator.h) evaluates each
// particle's springs from its own arrays and reads only the stage state, the masses and the
// environment here: built for it (DeviceForcePath::lattice), this class allocates the element
// arrays, the force slots, the gather table and the damping powers as placeholders of a few bytes
// and uploads nothing to them (at 1024 x 1024 in float32, about 780 bytes a particle, two thirds of
// the device step's memory).
//
// Which elements act is decided when the model is uploaded: live and its term on (the CPU's
// condition), as one flag per element. The model's revision is recorded; a model changed since
// (tearing, plasticity, live edits) is uploaded again with refresh().
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

// Which force passes a DeviceForces serves: the element passes (any sheet, and evaluate()), or
// only the state the lattice path reads.
enum class DeviceForcePath : std::uint8_t { general, lattice };

class DeviceForces {
 public:
  // Uploads the model. Throws GpuError when the device lacks the precision or the memory
  // ("the scene needs X MiB of device memory, <device> has Y MiB"), before allocating anything.
  // `power_slots`: how many sets of element damping powers element_power holds (one per stage
  // of a device step; evaluate() uses the first). `path`: which passes it serves (above).
  DeviceForces(Device& device, const ClothModel& model, Precision precision, ForceTerms terms,
               std::uint32_t power_slots = 1, DeviceForcePath path = DeviceForcePath::general);

  // The total force on every particle [particle_count()], as evaluate_forces computes it, and
  // the damping power of the springs (ForcePowers::damping, W). The drag power is not computed
  // on the device yet. The general path only.
  double evaluate(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                  std::span<Vec3> force);

  // Uploads the model's values again (rest values, constants, masses, broken springs, the
  // environment) after a change; its particle and element counts must be the same.
  void refresh(const ClothModel& model);
  std::uint64_t model_revision() const { return model_revision_; }
  // Takes `revision` as uploaded without uploading: the caller made the model's change on the
  // device itself (the lattice path's events), in arrays this class's general path does not share.
  void adopt_revision(std::uint64_t revision) { model_revision_ = revision; }

  // The arrays the element passes add the stage arrays to in float32 (gpu/shaders/stage_offsets.glsl):
  // a device step's state at the step's start. Until then, and for evaluate(), arrays of zeros
  // here, so that `position` and `velocity` are the state itself.
  void read_origin_from(const Buffer& origin_position, const Buffer& origin_velocity);

  // Records the connector and radial passes on `position` and `velocity`: every element's force
  // slots, and its damping power into element_power's set `power_slot`. The general path only.
  void record_element_passes(VkCommandBuffer commands, std::uint32_t power_slot) const;

  // Records what evaluate() computes on the `position` and `velocity` arrays: the element passes
  // (power set 0), the gather into `force` and the damping power's sum into `damping_power`. The
  // general path only.
  void record_forces(VkCommandBuffer commands) const;

  // Device memory for the arrays of a model of these counts (rows and cols unused), the state
  // and the scratch, bytes, on `path`.
  static std::uint64_t bytes_for(const LatticeCounts& counts, Precision precision, std::uint32_t power_slots = 1,
                                 DeviceForcePath path = DeviceForcePath::general);

  // The device's arrays, by the CPU's names: the state, the model, the scratch, the results.
  enum Array : std::uint32_t {
    position,
    velocity,
    origin_position,  // zeros (float32, the general path; else a placeholder): read_origin_from()
    origin_velocity,
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
    radial_fade_length,  // [2 radial_count]: the b and c arms' fade lengths, m
    radial_active,
    slot_force,
    element_power,
    force,
    block_power,    // the damping power's block sums
    damping_power,  // [1]
    array_count
  };
  Buffer& buffer(Array array) { return arrays_[array]; }
  std::uint32_t particle_count() const { return particles_; }
  std::uint32_t element_count() const { return connectors_ + radials_; }
  DeviceForcePath path() const { return path_; }

 private:
  void upload_model(const ClothModel& model);

  Device& device_;
  Precision precision_;
  ForceTerms terms_;
  std::uint32_t power_slots_;
  DeviceForcePath path_;
  std::uint64_t model_revision_;
  std::uint32_t particles_, connectors_, radials_;
  std::vector<Buffer> arrays_;  // [array_count]
  ComputePipeline connector_pass_, radial_pass_, gather_pass_, sum_pass_;
};

// A model's particle, connector and radial spring counts, and its rows and cols where they number
// its particles (0 else).
LatticeCounts element_counts(const ClothModel& model);

}  // namespace clothsim::gpu
