#include "gpu/state_transfer.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "core/assert.h"
#include "core/parallel.h"
#include "gpu/real_arrays.h"

namespace clothsim::gpu {

std::uint64_t state_fingerprint(const ClothState& state, int threads) {
  // Six FNV-1a lanes, one per coordinate of a particle's position and velocity: each lane's chain
  // of multiplies is independent of the others', so the six run side by side. One chain over
  // every word waited on the multiplies' latency: for a 1024 x 1024 sheet 7.0 ms on one core of
  // the 2-core VM and 3.5 ms on two, against 5.0 and 2.6 ms in lanes (medians of 9), which is
  // about what reading the 48 MB takes there. The host fingerprints the state up to three times
  // an advance.
  constexpr std::size_t kBlock = 4096;
  constexpr std::uint64_t kBasis = 1469598103934665603ull;
  constexpr std::uint64_t kPrime = 1099511628211ull;
  const std::size_t n = state.position.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint64_t> hashes(blocks);
  parallel_for(blocks, threads, [&](std::size_t block) {
    std::array<std::uint64_t, 6> lanes;
    lanes.fill(kBasis);
    const std::size_t end = std::min(n, (block + 1) * kBlock);
    for (std::size_t p = block * kBlock; p < end; ++p) {
      std::uint64_t words[6];
      std::memcpy(words, &state.position[p], 24);
      std::memcpy(words + 3, &state.velocity[p], 24);
      for (std::size_t k = 0; k < 6; ++k) lanes[k] = (lanes[k] ^ words[k]) * kPrime;
    }
    std::uint64_t hash = kBasis;
    for (std::uint64_t lane : lanes) hash = (hash ^ lane) * kPrime;
    hashes[block] = hash;
  });
  std::uint64_t hash = n;
  for (std::uint64_t block_hash : hashes) hash = (hash ^ block_hash) * kPrime + 0x9e3779b97f4a7c15ull;
  return hash;
}

void read_state(Device& device, StateArray position, StateArray velocity, const Buffer& staging, Precision precision,
                int threads, ClothState& state) {
  // Every array in one submission into the persistent staging buffer (highs, then the low parts
  // where there are any), then converted to doubles by every thread: a 1024 x 1024 sheet's 48 MB
  // each frame.
  const std::size_t particles = state.position.size();
  const std::uint64_t bytes = std::uint64_t{particles} * 3 * real_size(precision);
  const bool split = position.low != nullptr && velocity.low != nullptr;
  device.submit([&](VkCommandBuffer commands) {
    record_readback(commands, *position.high, staging, bytes, 0);
    record_readback(commands, *velocity.high, staging, bytes, bytes);
    if (split) {
      record_readback(commands, *position.low, staging, bytes, 2 * bytes);
      record_readback(commands, *velocity.low, staging, bytes, 3 * bytes);
    }
  });
  const std::byte* mapped = staging.mapped();
  // high + low is exact in double (split_state.glsl).
  const auto read = [&](std::uint64_t offset, std::size_t index) {
    const double high = load_real(mapped + offset, index, precision);
    return split ? high + load_real(mapped + offset + 2 * bytes, index, precision) : high;
  };
  parallel_for(particles, threads, [&](std::size_t p) {
    state.position[p] = {read(0, 3 * p), read(0, 3 * p + 1), read(0, 3 * p + 2)};
    state.velocity[p] = {read(bytes, 3 * p), read(bytes, 3 * p + 1), read(bytes, 3 * p + 2)};
  });
}

void write_state(Device& device, StateArray position, StateArray velocity, const Buffer& staging, Precision precision,
                 int threads, const ClothState& state) {
  const std::size_t particles = state.position.size();
  const std::uint64_t bytes = std::uint64_t{particles} * 3 * real_size(precision);
  const bool split = position.low != nullptr && velocity.low != nullptr;
  std::byte* mapped = staging.mapped();
  const auto write = [&](std::uint64_t offset, std::size_t index, double x) {
    if (!split) {
      store_real(mapped + offset, index, x, precision);
      return;
    }
    const SplitFloat value = split_real(x);
    std::memcpy(mapped + offset + 4 * index, &value.high, 4);
    std::memcpy(mapped + offset + 2 * bytes + 4 * index, &value.low, 4);
  };
  parallel_for(particles, threads, [&](std::size_t p) {
    for (int k = 0; k < 3; ++k) {
      write(0, 3 * p + k, state.position[p][k]);
      write(bytes, 3 * p + k, state.velocity[p][k]);
    }
  });
  device.submit([&](VkCommandBuffer commands) {
    record_upload(commands, staging, *position.high, bytes, 0);
    record_upload(commands, staging, *velocity.high, bytes, bytes);
    if (split) {
      record_upload(commands, staging, *position.low, bytes, 2 * bytes);
      record_upload(commands, staging, *velocity.low, bytes, 3 * bytes);
    }
  });
}

std::uint64_t particle_write_bytes(std::size_t particles, Precision precision) {
  // Two arrays (positions, velocities) of 3 Reals a particle, with their low parts in float32.
  return std::uint64_t{particles} * 3 * real_size(precision) * (splits_state(precision) ? 4 : 2);
}

void record_particle_writes(VkCommandBuffer commands, StateArray position, StateArray velocity, const Buffer& staging,
                            Precision precision, std::span<const std::uint32_t> particles, const ClothState& state) {
  CLOTHSIM_ASSERT(staging.bytes() >= particle_write_bytes(particles.size(), precision), "staging holds the writes");
  const std::uint64_t real = real_size(precision);
  const std::uint64_t vector = 3 * real;
  const bool split = position.low != nullptr && velocity.low != nullptr;
  std::byte* mapped = staging.mapped();
  // In staging: the particles' positions, then their velocities, each 3 Reals (in float32 the high
  // parts, then the low parts of both).
  const std::uint64_t block = particles.size() * vector;
  std::vector<VkBufferCopy> high_position, high_velocity, low_position, low_velocity;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const std::uint32_t p = particles[i];
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 3 * i + static_cast<std::size_t>(k);
      if (!split) {
        store_real(mapped, at, state.position[p][k], precision);
        store_real(mapped + block, at, state.velocity[p][k], precision);
        continue;
      }
      const SplitFloat x = split_real(state.position[p][k]);
      const SplitFloat v = split_real(state.velocity[p][k]);
      std::memcpy(mapped + 4 * at, &x.high, 4);
      std::memcpy(mapped + block + 4 * at, &v.high, 4);
      std::memcpy(mapped + 2 * block + 4 * at, &x.low, 4);
      std::memcpy(mapped + 3 * block + 4 * at, &v.low, 4);
    }
    const std::uint64_t from = i * vector;
    const std::uint64_t to = std::uint64_t{p} * vector;
    high_position.push_back({from, to, vector});
    high_velocity.push_back({block + from, to, vector});
    low_position.push_back({2 * block + from, to, vector});
    low_velocity.push_back({3 * block + from, to, vector});
  }
  record_upload(commands, staging, *position.high, high_position);
  record_upload(commands, staging, *velocity.high, high_velocity);
  if (split) {
    record_upload(commands, staging, *position.low, low_position);
    record_upload(commands, staging, *velocity.low, low_velocity);
  }
}

}  // namespace clothsim::gpu
