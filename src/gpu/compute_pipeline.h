// A compute pipeline from embedded SPIR-V (embedded_shaders.h): its storage-buffer bindings
// 0..N-1, one push-constant block, the workgroup size as specialization constant 0
// (`layout(local_size_x_id = 0) in;` in the shader), and one descriptor set.
//
// Use: bind() the buffers (outside a submission), then dispatch() inside Device::submit(). The one
// descriptor set means a pipeline serves one binding of buffers per submission; a step that runs
// the same pass on different buffers will want a set per binding (docs/gpu.md, "Not done yet").
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/device.h"

namespace clothsim::gpu {

class ComputePipeline {
 public:
  ComputePipeline(Device& device, std::span<const std::uint32_t> spirv, std::uint32_t binding_count,
                  std::uint32_t push_constant_bytes, std::uint32_t workgroup_size = 64);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // Buffers for bindings 0, 1, ... in order: as many as the pipeline has bindings.
  void bind(std::span<const Buffer* const> buffers);
  // Pushes `push_constants` (push_constant_bytes of them) and dispatches enough workgroups for
  // `invocations` (in rows of y beyond the device's x limit: shaders/invocation.glsl), followed
  // by compute_write_barrier(). Throws GpuError if that is more workgroups than the device
  // dispatches at once.
  void dispatch(VkCommandBuffer commands, const void* push_constants, std::uint32_t invocations) const;
  // The workgroups dispatch() runs for `invocations`: ceil(invocations / workgroup size).
  std::uint32_t workgroups(std::uint32_t invocations) const;

 private:
  void release();

  VkDevice device_ = VK_NULL_HANDLE;
  std::uint32_t binding_count_ = 0;
  std::uint32_t push_constant_bytes_ = 0;
  std::uint32_t workgroup_size_ = 0;
  std::uint32_t max_workgroups_[2] = {0, 0};  // x and y
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

// The pipeline of the embedded shader `name` in `precision` (embedded_shaders.h).
ComputePipeline shader_pipeline(Device& device, std::string_view name, Precision precision,
                                std::uint32_t binding_count, std::uint32_t push_constant_bytes,
                                std::uint32_t workgroup_size = 64);

// The workgroups of `workgroup_size` that cover `items` invocations: what arrays of per-workgroup
// results hold, sized before any pipeline exists.
constexpr std::uint32_t workgroups_for(std::uint64_t items, std::uint32_t workgroup_size) {
  return static_cast<std::uint32_t>((items + workgroup_size - 1) / workgroup_size);
}

}  // namespace clothsim::gpu
