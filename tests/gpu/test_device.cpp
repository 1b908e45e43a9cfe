// The Vulkan layer itself: devices listed, a device opened with the validation layers, buffers
// copied there and back, the fingerprint by which the host sees a changed state, and the clear
// errors: a device that does not exist, a scene larger than the device's memory, a shader that
// was not built.
#include "gpu/device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/embedded_shaders.h"
#include "gpu/gpu_error.h"
#include "gpu/instance.h"
#include "gpu/state_transfer.h"
#include "gpu_fixture.h"

namespace clothsim {
namespace {

using testing::GpuTest;

TEST_F(GpuTest, ListsTheDeviceItOpened) {
  const gpu::Instance instance;
  const std::vector<gpu::DeviceInfo> devices = instance.devices();
  ASSERT_FALSE(devices.empty());
  EXPECT_EQ(devices[0].name, device().info().name);
  EXPECT_EQ(devices[0].index, 0u);
  EXPECT_FALSE(devices[0].api_version.empty());
  EXPECT_GT(devices[0].device_local_bytes, 0u);
}

TEST_F(GpuTest, BufferRoundTrip) {
  std::vector<std::uint32_t> words(1000);
  std::iota(words.begin(), words.end(), 7u);
  gpu::Buffer buffer(device(), words.size() * 4, gpu::Memory::device_local);
  gpu::upload(device(), buffer, std::as_bytes(std::span(words)));
  std::vector<std::uint32_t> back(words.size());
  gpu::download(device(), buffer, std::as_writable_bytes(std::span(back)));
  EXPECT_EQ(back, words);
}

TEST_F(GpuTest, NoSuchDeviceIsAClearError) {
  try {
    gpu::Device missing(gpu::DeviceOptions{1000, false});
    FAIL() << "device 1000 opened";
  } catch (const gpu::GpuError& error) {
    EXPECT_NE(std::string(error.what()).find("no Vulkan device 1000"), std::string::npos) << error.what();
  }
}

TEST_F(GpuTest, SceneLargerThanTheDeviceIsAClearError) {
  const std::uint64_t too_much = device().info().device_local_bytes + (std::uint64_t{1} << 30);
  try {
    device().require_memory(too_much, "the scene");
    FAIL() << "no error";
  } catch (const gpu::GpuError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("the scene needs " + gpu::mebibytes(too_much) + " of device memory"), std::string::npos)
        << message;
    EXPECT_NE(message.find(device().info().name), std::string::npos) << message;
  }
  EXPECT_THROW(gpu::Buffer(device(), too_much, gpu::Memory::device_local), gpu::GpuError);
}

TEST_F(GpuTest, EveryShaderIsEmbeddedInBothPrecisions) {
  for (const char* name : {"accumulate_connector_springs", "accumulate_radial_springs"}) {
    for (gpu::Precision precision : {gpu::Precision::float32, gpu::Precision::float64}) {
      const std::span<const std::uint32_t> code = gpu::embedded_shader(gpu::shader_variant(name, precision));
      ASSERT_GT(code.size(), 5u);
      EXPECT_EQ(code[0], 0x07230203u) << "SPIR-V magic number";
    }
  }
  EXPECT_THROW(gpu::embedded_shader("no_such_shader.float32"), gpu::GpuError);
}

// The device integrators upload the state again when its fingerprint moved
// (gpu/state_transfer.h): a change of one coordinate by one ulp, anywhere, in any of the six
// lanes and any block, must move it, and the thread count must not.
TEST(StateFingerprint, MovesWithAnyCoordinateAndNotWithTheThreads) {
  ClothState state;
  const std::size_t n = 9000;  // three blocks of 4096, the last partial
  for (std::size_t p = 0; p < n; ++p) {
    state.position.push_back({0.5 * double(p), -1.25, 1.0 / double(p + 1)});
    state.velocity.push_back({0.0, 0.01 * double(p % 17), -2.0});
  }
  const std::uint64_t original = gpu::state_fingerprint(state, 1);
  EXPECT_EQ(gpu::state_fingerprint(state, 2), original);
  EXPECT_EQ(gpu::state_fingerprint(state, 7), original);
  std::size_t moved = 0, changes = 0;
  for (std::size_t p = 0; p < n; p += 97) {
    for (int k = 0; k < 6; ++k) {
      ClothState changed = state;
      Vec3& v = k < 3 ? changed.position[p] : changed.velocity[p];
      double& x = k % 3 == 0 ? v.x : k % 3 == 1 ? v.y : v.z;
      x = std::nextafter(x, 1e300);
      ++changes;
      if (gpu::state_fingerprint(changed, 2) != original) ++moved;
    }
  }
  EXPECT_EQ(moved, changes);
  // Two particles' states swapped: the same numbers in another order.
  ClothState swapped = state;
  std::swap(swapped.position[10], swapped.position[5000]);
  EXPECT_NE(gpu::state_fingerprint(swapped, 2), original);
}

}  // namespace
}  // namespace clothsim
