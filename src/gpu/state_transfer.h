// The state between the host and a device integrator (device_integrator.h, device_implicit_euler.h),
// which keep it on the device between advances: the fingerprint the host compares to see whether a
// caller changed the state since the device last had it, and the read-back of positions and
// velocities.
#pragma once

#include <cstdint>
#include <span>

#include "gpu/buffer.h"
#include "gpu/device.h"
#include "model/cloth_model.h"

namespace clothsim::gpu {

// A 64-bit fingerprint of the state's positions and velocities, instead of a copy of the state:
// per block of particles six FNV-1a lanes, one per coordinate, folded together; the blocks'
// hashes combined in order. The same for any thread count.
std::uint64_t state_fingerprint(const ClothState& state, int threads);

// A state array on the device: 3 Reals per particle, and in float32 optionally their low parts
// (shaders/split_state.glsl), the value being high + low.
struct StateArray {
  const Buffer* high = nullptr;
  const Buffer* low = nullptr;
};

// Both directions go through `staging`, host-visible and persistent (no allocation per transfer),
// laid out as the highs of the positions, then of the velocities, then their low parts where the
// arrays have them, each 3 Reals a particle.
//
// Copies `position` and `velocity` into `staging` in one submission and converts them into the
// state's doubles on `threads` threads.
void read_state(Device& device, StateArray position, StateArray velocity, const Buffer& staging, Precision precision,
                int threads, ClothState& state);
// Converts the state's positions and velocities into `staging` on `threads` threads (in float32
// with low parts, split as split_state.glsl holds them: split_real) and copies them into `position`
// and `velocity` in one submission.
void write_state(Device& device, StateArray position, StateArray velocity, const Buffer& staging, Precision precision,
                 int threads, const ClothState& state);

// Records the writes of the positions and velocities of a few `particles` (the anchored ones)
// from `state` into `position` and `velocity`, through `staging` (host-visible, at least
// particle_write_bytes of them), which it fills now: a part of a submission the caller records.
std::uint64_t particle_write_bytes(std::size_t particles, Precision precision);
void record_particle_writes(VkCommandBuffer commands, StateArray position, StateArray velocity, const Buffer& staging,
                            Precision precision, std::span<const std::uint32_t> particles, const ClothState& state);

}  // namespace clothsim::gpu
