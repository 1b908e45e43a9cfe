// A frame's energies and the Simulation's state checks, computed on the device where the state
// lives (issue 22 item 3; docs/gpu.md, "Frames without the host"). At the end of an advance the
// Simulation sums every spring's energy for the energy balance and energy.csv, and looks for a
// non-finite state or an exploded connector. On a 1024 x 1024 sheet that is 8 million springs,
// each radial one an arctangent: 28 ms of the host's time per frame on an H200 machine's 16
// threads, a third of the device's time for the frame's steps. This pass does it in one dispatch
// over the lattice (three on the general path: the particles, the connectors, the radial springs)
// and reads back 48 bytes a workgroup of 256 (196 kB at 1024 x 1024): the five terms of
// EnergyReport and the count of items that fail a check, summed by the host in workgroup order, so
// the result is the same on every run on a device.
//
// The sums are the host's to rounding: the same element formulas (forces/element_math.inc),
// double arithmetic in both precisions, float32's state as its two floats a coordinate. In
// float32 the springs' parameters and the masses are the device's, rounded to float, which its
// forces use too (tests/gpu/test_device_state_checks.cpp states the bound).
#pragma once

#include <cstdint>
#include <functional>

#include "forces/forces.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/device_forces.h"
#include "gpu/state_transfer.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim::gpu {

class StateChecksPass {
 public:
  // The pass computes in double: it needs shaderFloat64 in either precision. Its stretch check
  // reads the connectors' parameters, which the device holds only with their force term on.
  static bool runs_on(const Device& device) { return device.info().float64; }
  static bool runs_with(ForceTerms terms) { return (terms & kConnectorSprings) != 0; }
  // Device memory it holds for a model of these counts on `path`, bytes.
  static std::uint64_t bytes_for(const LatticeCounts& counts, DeviceForcePath path);

  // For a model of these counts whose state, masses and spring parameters are in `precision`, read
  // from the lattice path's arrays (shaders/state_checks.comp: each particle's own springs) or
  // DeviceForces' element arrays (shaders/state_checks_elements.comp).
  StateChecksPass(Device& device, Precision precision, const LatticeCounts& counts, DeviceForcePath path);

  // The arrays the lattice path reads: the state (with its low parts in float32), the masses,
  // `lattice_params` and `event_params` (shaders/device_step.h).
  void bind_lattice(StateArray position, StateArray velocity, const Buffer& mass, const Buffer& lattice_params,
                    const Buffer& event_params);
  // The general path's: the state, and DeviceForces' masses and element arrays.
  void bind_elements(StateArray position, StateArray velocity, DeviceForces& forces);
  // Runs the pass on the state as the device holds it, after what `before` records into the same
  // submission (the state's last changes), and waits for its sums: the energies as compute_energy
  // reports them for `terms` (the springs whose term is off are absent on the device already),
  // and whether any item failed. `model` gives the lattice's shape and the gravity.
  StateChecks run(const ClothModel& model, ForceTerms terms, double explosion_stretch,
                  const std::function<void(VkCommandBuffer)>& before);

 private:
  Device& device_;
  DeviceForcePath path_;
  LatticeCounts counts_;
  ComputePipeline pass_;
  Buffer block_checks_;  // [blocks][kStateCheckReals] doubles, device-local
  Buffer readback_;      // the same, host-visible
};

}  // namespace clothsim::gpu
