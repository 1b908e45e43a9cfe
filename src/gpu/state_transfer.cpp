#include "gpu/state_transfer.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/parallel.h"
#include "gpu/real_arrays.h"

namespace clothsim::gpu {

std::uint64_t state_fingerprint(const ClothState& state, int threads) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t n = state.position.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint64_t> hashes(blocks);
  parallel_for(blocks, threads, [&](std::size_t block) {
    std::uint64_t hash = 1469598103934665603ull;
    const auto mix = [&hash](const Vec3& v) {
      std::uint64_t words[3];
      std::memcpy(words, &v, sizeof words);
      for (std::uint64_t word : words) hash = (hash ^ word) * 1099511628211ull;
    };
    const std::size_t end = std::min(n, (block + 1) * kBlock);
    for (std::size_t p = block * kBlock; p < end; ++p) {
      mix(state.position[p]);
      mix(state.velocity[p]);
    }
    hashes[block] = hash;
  });
  std::uint64_t hash = n;
  for (std::uint64_t block_hash : hashes) hash = (hash ^ block_hash) * 1099511628211ull + 0x9e3779b97f4a7c15ull;
  return hash;
}

void read_state(Device& device, const Buffer& position, const Buffer& velocity, const Buffer& staging,
                Precision precision, int threads, ClothState& state) {
  // Both arrays in one submission into the persistent staging buffer, then converted to doubles
  // by every thread: a 1024 x 1024 sheet's 48 MB each frame.
  const std::size_t particles = state.position.size();
  const std::uint64_t bytes = std::uint64_t{particles} * 3 * real_size(precision);
  device.submit([&](VkCommandBuffer commands) {
    record_readback(commands, position, staging, bytes, 0);
    record_readback(commands, velocity, staging, bytes, bytes);
  });
  const std::byte* mapped = staging.mapped();
  const auto read = [&](std::uint64_t offset, std::size_t index) { return load_real(mapped + offset, index, precision); };
  parallel_for(particles, threads, [&](std::size_t p) {
    state.position[p] = {read(0, 3 * p), read(0, 3 * p + 1), read(0, 3 * p + 2)};
    state.velocity[p] = {read(bytes, 3 * p), read(bytes, 3 * p + 1), read(bytes, 3 * p + 2)};
  });
}

}  // namespace clothsim::gpu
