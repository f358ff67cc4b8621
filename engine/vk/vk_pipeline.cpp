#include "engine/vk/vk_pipeline.h"

#include <chrono>
#include <cstring>

#include "engine/base/error.h"
#include "engine/vk/shader_table.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {

ComputePipeline& ComputePipeline::operator=(ComputePipeline&& o) noexcept {
  if (this != &o) {
    release();
    ctx = o.ctx;
    name = std::move(o.name);
    module = o.module;
    setLayout = o.setLayout;
    layout = o.layout;
    pipeline = o.pipeline;
    bindings = std::move(o.bindings);
    pushBytes = o.pushBytes;
    createMs = o.createMs;
    o.ctx = nullptr;
    o.module = VK_NULL_HANDLE;
    o.setLayout = VK_NULL_HANDLE;
    o.layout = VK_NULL_HANDLE;
    o.pipeline = VK_NULL_HANDLE;
  }
  return *this;
}

void ComputePipeline::release() {
  if (ctx && ctx->device) {
    if (pipeline) vkDestroyPipeline(ctx->device, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(ctx->device, layout, nullptr);
    if (setLayout) vkDestroyDescriptorSetLayout(ctx->device, setLayout, nullptr);
    if (module) vkDestroyShaderModule(ctx->device, module, nullptr);
  }
  ctx = nullptr;
  pipeline = VK_NULL_HANDLE;
  layout = VK_NULL_HANDLE;
  setLayout = VK_NULL_HANDLE;
  module = VK_NULL_HANDLE;
}

SpecConstant specFloat(uint32_t id, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  return {id, bits};
}

ComputePipeline createComputePipeline(Context& ctx, const char* shaderName, std::vector<VkDescriptorType> bindings,
                                      uint32_t pushBytes, const std::vector<SpecConstant>& spec) {
  const EmbeddedShader& shader = findShader(shaderName);
  ComputePipeline p;
  p.ctx = &ctx;
  p.name = shaderName;
  p.bindings = std::move(bindings);
  p.pushBytes = pushBytes;

  VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = shader.bytes;
  smi.pCode = shader.code;
  REFRAX_VK(vkCreateShaderModule(ctx.device, &smi, nullptr, &p.module));

  std::vector<VkDescriptorSetLayoutBinding> lb(p.bindings.size());
  for (size_t i = 0; i < lb.size(); i++) {
    lb[i] = {};
    lb[i].binding = uint32_t(i);
    lb[i].descriptorType = p.bindings[i];
    lb[i].descriptorCount = 1;
    lb[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dli.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  dli.bindingCount = uint32_t(lb.size());
  dli.pBindings = lb.data();
  REFRAX_VK(vkCreateDescriptorSetLayout(ctx.device, &dli, nullptr, &p.setLayout));

  VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &p.setLayout;
  pli.pushConstantRangeCount = pushBytes ? 1 : 0;
  pli.pPushConstantRanges = &pcr;
  REFRAX_VK(vkCreatePipelineLayout(ctx.device, &pli, nullptr, &p.layout));

  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (auto& s : spec) {
    entries.push_back({s.id, uint32_t(values.size() * 4), 4});
    values.push_back(s.value);
  }
  VkSpecializationInfo si{uint32_t(entries.size()), entries.data(), values.size() * 4, values.data()};

  VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpi.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpi.stage.module = p.module;
  cpi.stage.pName = "main";
  cpi.stage.pSpecializationInfo = spec.empty() ? nullptr : &si;
  cpi.layout = p.layout;
  auto t0 = std::chrono::steady_clock::now();
  REFRAX_VK(vkCreateComputePipelines(ctx.device, VK_NULL_HANDLE, 1, &cpi, nullptr, &p.pipeline));
  p.createMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return p;
}

Binding bind(const Buffer& b) {
  Binding r{kStorageBuffer};
  r.buffer = b.buffer;
  return r;
}
Binding bind(const AccelStruct& a) {
  Binding r{kAccelStruct};
  r.accel = a.handle;
  return r;
}
Binding bindImage(VkImageView view) {
  Binding r{kStorageImage};
  r.view = view;
  return r;
}

namespace {
// Binds the pipeline, pushes its bindings (checked against its list) and push constants.
void cmdBindForDispatch(VkCommandBuffer cb, const ComputePipeline& p, std::initializer_list<Binding> bindings, const void* push) {
  if (bindings.size() != p.bindings.size())
    fail("dispatch of '" + p.name + "' with " + std::to_string(bindings.size()) + " bindings, pipeline declares " +
         std::to_string(p.bindings.size()));
  size_t n = bindings.size();
  std::vector<VkWriteDescriptorSet> writes(n);
  std::vector<VkDescriptorBufferInfo> bufferInfos(n);
  std::vector<VkDescriptorImageInfo> imageInfos(n);
  std::vector<VkWriteDescriptorSetAccelerationStructureKHR> accelInfos(n);
  std::vector<VkAccelerationStructureKHR> accels(n);
  size_t i = 0;
  for (const Binding& b : bindings) {
    if (b.type != p.bindings[i]) fail("dispatch of '" + p.name + "': binding " + std::to_string(i) + " has the wrong type");
    VkWriteDescriptorSet& w = writes[i];
    w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = uint32_t(i);
    w.descriptorCount = 1;
    w.descriptorType = b.type;
    if (b.type == kStorageBuffer) {
      bufferInfos[i] = {b.buffer, 0, VK_WHOLE_SIZE};
      w.pBufferInfo = &bufferInfos[i];
    } else if (b.type == kAccelStruct) {
      accels[i] = b.accel;
      accelInfos[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
      accelInfos[i].accelerationStructureCount = 1;
      accelInfos[i].pAccelerationStructures = &accels[i];
      w.pNext = &accelInfos[i];
    } else {
      imageInfos[i] = {VK_NULL_HANDLE, b.view, VK_IMAGE_LAYOUT_GENERAL};
      w.pImageInfo = &imageInfos[i];
    }
    i++;
  }
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  if (n) vkCmdPushDescriptorSetKHR(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, uint32_t(n), writes.data());
  if (p.pushBytes) vkCmdPushConstants(cb, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, p.pushBytes, push);
}
}  // namespace

void cmdDispatch(VkCommandBuffer cb, const ComputePipeline& p, std::initializer_list<Binding> bindings, const void* push,
                 uint32_t gx, uint32_t gy, uint32_t gz) {
  cmdBindForDispatch(cb, p, bindings, push);
  vkCmdDispatch(cb, gx, gy, gz);
  if (p.ctx && p.ctx->profiler) p.ctx->profiler->dispatches++;
}

void cmdDispatchIndirect(VkCommandBuffer cb, const ComputePipeline& p, std::initializer_list<Binding> bindings, const void* push,
                         const Buffer& args, VkDeviceSize offset) {
  if (offset % 4 != 0 || offset + sizeof(VkDispatchIndirectCommand) > args.size)
    fail("indirect dispatch of '" + p.name + "': its group counts lie outside the buffer");
  cmdBindForDispatch(cb, p, bindings, push);
  vkCmdDispatchIndirect(cb, args.buffer, offset);
  if (p.ctx && p.ctx->profiler) p.ctx->profiler->dispatches++;
}

}  // namespace refrax
