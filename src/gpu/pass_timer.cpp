#include "gpu/pass_timer.h"

#include "core/assert.h"
#include "gpu/instance.h"

namespace clothsim::gpu {

PassTimer::PassTimer(Device& device, std::uint32_t marks) : device_(device), capacity_(marks + 1) {
  const std::uint32_t bits = device.timestamp_valid_bits();
  const double period_ns = device.limits().timestampPeriod;
  if (bits == 0 || !(period_ns > 0.0)) return;
  valid_mask_ = bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
  seconds_per_tick_ = 1e-9 * period_ns;
  VkQueryPoolCreateInfo create{};
  create.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
  create.queryType = VK_QUERY_TYPE_TIMESTAMP;
  create.queryCount = capacity_;
  check(vkCreateQueryPool(device.handle(), &create, nullptr, &pool_), "vkCreateQueryPool");
  stages_.reserve(marks);
}

PassTimer::~PassTimer() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_.handle(), pool_, nullptr);
}

void PassTimer::begin(VkCommandBuffer commands) {
  if (!enabled()) return;
  stages_.clear();
  vkCmdResetQueryPool(commands, pool_, 0, capacity_);
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, pool_, 0);
}

void PassTimer::mark(VkCommandBuffer commands, StepStage stage) {
  if (!enabled()) return;
  CLOTHSIM_ASSERT(stages_.size() + 1 < capacity_, "PassTimer: more marks than it was made for");
  stages_.push_back(stage);
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, pool_,
                      static_cast<std::uint32_t>(stages_.size()));
}

void PassTimer::add_to(StepProfile& profile) const {
  last_seconds_ = 0.0;
  if (!enabled() || stages_.empty()) return;
  const auto count = static_cast<std::uint32_t>(stages_.size() + 1);
  std::vector<std::uint64_t> ticks(count);
  check(vkGetQueryPoolResults(device_.handle(), pool_, 0, count, count * sizeof(std::uint64_t), ticks.data(),
                              sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  for (std::size_t k = 0; k < stages_.size(); ++k) {
    // Modulo the valid bits, so that a counter that wrapped between two marks still subtracts.
    const std::uint64_t elapsed = (ticks[k + 1] - ticks[k]) & valid_mask_;
    const double seconds = static_cast<double>(elapsed) * seconds_per_tick_;
    profile.add(stages_[k], seconds);
    last_seconds_ += seconds;
  }
}

}  // namespace clothsim::gpu
