// The device the GPU tests run on: device 0 with the validation layers where they are installed,
// opened once per test program. No device fails the test with the reason (CI has lavapipe).
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "gpu/device.h"
#include "gpu/gpu_error.h"

namespace clothsim::testing {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (device_ || !open_error_.empty()) return;
    try {
      device_ = std::make_unique<gpu::Device>(gpu::DeviceOptions{0, true});
      std::printf("Vulkan device 0: %s, validation layers %s\n", device_->info().name.c_str(),
                  device_->instance().validation_enabled() ? "on" : "not installed");
    } catch (const gpu::GpuError& error) {
      open_error_ = error.what();
    }
  }
  static void TearDownTestSuite() { device_.reset(); }

  void SetUp() override {
    ASSERT_TRUE(device_) << "the GPU tests need a Vulkan device (lavapipe: apt-get install mesa-vulkan-drivers): "
                         << open_error_;
    validation_errors_before_ = device_->instance().validation_errors();
  }
  void TearDown() override {
    if (device_) {
      EXPECT_EQ(device_->instance().validation_errors(), validation_errors_before_)
          << "Vulkan validation errors (printed above)";
    }
  }

  static gpu::Device& device() { return *device_; }

 private:
  static inline std::unique_ptr<gpu::Device> device_;
  static inline std::string open_error_;
  std::uint64_t validation_errors_before_ = 0;
};

}  // namespace clothsim::testing
