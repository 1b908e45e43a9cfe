#include "gpu/compute_pipeline.h"

#include <algorithm>
#include <string>
#include <vector>

#include "gpu/embedded_shaders.h"
#include "gpu/gpu_error.h"

namespace clothsim::gpu {

ComputePipeline::ComputePipeline(Device& device, std::span<const std::uint32_t> spirv, std::uint32_t binding_count,
                                 std::uint32_t push_constant_bytes, std::uint32_t workgroup_size)
    : device_(device.handle()),
      binding_count_(binding_count),
      push_constant_bytes_(push_constant_bytes),
      workgroup_size_(workgroup_size),
      max_workgroups_{device.limits().maxComputeWorkGroupCount[0], device.limits().maxComputeWorkGroupCount[1]} {
  if (workgroup_size > device.limits().maxComputeWorkGroupSize[0]) {
    throw GpuError("workgroup size " + std::to_string(workgroup_size) + " is above the device's limit");
  }
  try {
    VkShaderModuleCreateInfo module{};
    module.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    module.codeSize = spirv.size_bytes();
    module.pCode = spirv.data();
    check(vkCreateShaderModule(device_, &module, nullptr, &module_), "vkCreateShaderModule");

    std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
    for (std::uint32_t i = 0; i < binding_count; ++i) {
      bindings[i].binding = i;
      bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      bindings[i].descriptorCount = 1;
      bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set_layout{};
    set_layout.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_layout.bindingCount = binding_count;
    set_layout.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(device_, &set_layout, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");

    const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
    VkPipelineLayoutCreateInfo layout{};
    layout.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout.setLayoutCount = 1;
    layout.pSetLayouts = &set_layout_;
    layout.pushConstantRangeCount = push_constant_bytes > 0 ? 1 : 0;
    layout.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(device_, &layout, nullptr, &layout_), "vkCreatePipelineLayout");

    const VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
    VkSpecializationInfo specialization{};
    specialization.mapEntryCount = 1;
    specialization.pMapEntries = &entry;
    specialization.dataSize = sizeof(std::uint32_t);
    specialization.pData = &workgroup_size_;
    VkComputePipelineCreateInfo pipeline{};
    pipeline.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    pipeline.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipeline.stage.module = module_;
    pipeline.stage.pName = "main";
    pipeline.stage.pSpecializationInfo = &specialization;
    pipeline.layout = layout_;
    check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_),
          "vkCreateComputePipelines");

    const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, binding_count};
    VkDescriptorPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool.maxSets = 1;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &pool_size;
    check(vkCreateDescriptorPool(device_, &pool, nullptr, &pool_), "vkCreateDescriptorPool");
    VkDescriptorSetAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    allocate.descriptorPool = pool_;
    allocate.descriptorSetCount = 1;
    allocate.pSetLayouts = &set_layout_;
    check(vkAllocateDescriptorSets(device_, &allocate, &set_), "vkAllocateDescriptorSets");
  } catch (...) {
    release();
    throw;
  }
}

ComputePipeline::~ComputePipeline() { release(); }

// Destroys what exists; Vulkan ignores the null handles of what was never made.
void ComputePipeline::release() {
  vkDestroyDescriptorPool(device_, pool_, nullptr);  // frees the set
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  vkDestroyShaderModule(device_, module_, nullptr);
}

void ComputePipeline::bind(std::span<const Buffer* const> buffers) {
  if (buffers.size() != binding_count_) {
    throw GpuError("a pipeline with " + std::to_string(binding_count_) + " bindings was given " +
                   std::to_string(buffers.size()) + " buffers");
  }
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::uint32_t i = 0; i < binding_count_; ++i) {
    infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set_;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(device_, binding_count_, writes.data(), 0, nullptr);
}

std::uint32_t ComputePipeline::workgroups(std::uint32_t invocations) const {
  return workgroups_for(invocations, workgroup_size_);
}

ComputePipeline shader_pipeline(Device& device, std::string_view name, Precision precision,
                                std::uint32_t binding_count, std::uint32_t push_constant_bytes,
                                std::uint32_t workgroup_size) {
  return ComputePipeline(device, embedded_shader(shader_variant(name, precision)), binding_count, push_constant_bytes,
                         workgroup_size);
}

void ComputePipeline::dispatch(VkCommandBuffer commands, const void* push_constants, std::uint32_t invocations) const {
  // More workgroups than the device dispatches in x go into rows of y (shaders/invocation.glsl);
  // the last row's surplus invocations fall past `invocations`, which every shader checks.
  const std::uint32_t groups = workgroups(invocations);
  const std::uint32_t groups_x = std::min(groups, max_workgroups_[0]);
  const std::uint32_t groups_y = groups_x == 0 ? 0 : (groups + groups_x - 1) / groups_x;
  if (groups_y > max_workgroups_[1]) {
    throw GpuError(std::to_string(invocations) + " invocations need " + std::to_string(groups) +
                   " workgroups, more than the device dispatches at once (" + std::to_string(max_workgroups_[0]) +
                   " x " + std::to_string(max_workgroups_[1]) + ")");
  }
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
  if (push_constant_bytes_ > 0) {
    vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes_, push_constants);
  }
  if (groups > 0) vkCmdDispatch(commands, groups_x, groups_y, 1);
  compute_write_barrier(commands);
}

}  // namespace clothsim::gpu
