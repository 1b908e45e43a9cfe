// Device time per stage of the step (core/step_profile.h) from timestamps between a recorded
// command buffer's passes, so that `clothsim run --profile` on the Vulkan backend names the same
// stages as on the CPU ("forces", "stage sums", "solution and error", ...).
//
// Use: while recording, begin() once, then mark(stage) after the last pass of each run of passes
// that belong to `stage`; after each submission of the buffer, add_to() the time between each mark
// and the one before it to the stage it names. A timestamp after a pass's barrier is written when
// the pass is done, so each interval holds its passes and the barriers between them. A device
// without timestamps on its compute queue records nothing, and add_to() adds nothing.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/step_profile.h"
#include "gpu/device.h"

namespace clothsim::gpu {

class PassTimer {
 public:
  // A timer for at most `marks` marks in one command buffer.
  PassTimer(Device& device, std::uint32_t marks);
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  bool enabled() const { return pool_ != VK_NULL_HANDLE; }
  // At the start of recording: resets the timestamps and takes the first.
  void begin(VkCommandBuffer commands);
  // After the passes of `stage` since the last mark.
  void mark(VkCommandBuffer commands, StepStage stage);
  // After a submission of the recorded buffer: each interval's device time into `profile`.
  void add_to(StepProfile& profile) const;
  // The device time of the last submission that add_to() read, s.
  double last_seconds() const { return last_seconds_; }

 private:
  Device& device_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  std::uint32_t capacity_ = 0;     // timestamps the pool holds: marks + 1
  std::uint64_t valid_mask_ = 0;   // the bits of a timestamp the queue writes
  double seconds_per_tick_ = 0.0;  // VkPhysicalDeviceLimits::timestampPeriod, in s
  std::vector<StepStage> stages_;  // [marks]: the stage of the interval that ends at each mark
  mutable double last_seconds_ = 0.0;
};

}  // namespace clothsim::gpu
