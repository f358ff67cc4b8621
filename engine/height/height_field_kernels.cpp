// Height field kernels: pipeline cache, the loop-based forward and the backward passes.
#include <algorithm>
#include <functional>

#include "engine/base/error.h"
#include "engine/height/height_encoding.h"
#include "engine/height/height_field_kernels.h"
#include "engine/height/height_kernel_shapes.h"
#include "engine/vk/shader_table.h"
#include "engine/vk/vk_context.h"

namespace refrax {

const ComputePipeline& heightPipeline(const HeightField& hf, const std::string& key, const std::function<ComputePipeline()>& make) {
  auto& cache = hf.pipelines->byName;
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, make()).first;
  return it->second;
}

std::vector<SpecConstant> heightShapeConstants(const HeightFieldConfig& c) {
  return {{0, heightInputCount(c)}, {1, c.width}, {2, c.hiddenLayers}, specFloat(3, c.leakySlope)};
}

HeightBackpropKernel heightBackpropKernel(const HeightField& hf) {
  const HeightFieldConfig& c = hf.config;
  const VkPhysicalDeviceLimits& limits = hf.ctx->properties.limits;
  std::string fused = heightBackpropKernelName(c.width, c.hiddenLayers, hf.kernelOctaves);
  const bool padded = hf.kernelOctaves != c.octaves;
  // A padded pass 1 leaves a scratch layout only the gradient tiles read (their input stride is pushed).
  if (!hf.forceGenericBackward && c.width <= kHeightFusedMaxWidth && heightShaderEmbedded(fused) &&
      (!padded || heightGradTilesAvailable(hf)) && limits.maxComputeWorkGroupInvocations >= kHeightKernelGroup &&
      limits.maxComputeWorkGroupSize[0] >= kHeightKernelGroup && limits.maxComputeSharedMemorySize >= kHeightStageFloats * 4) {
    const ComputePipeline& p = heightPipeline(hf, fused, [&] {
      return createComputePipeline(*hf.ctx, fused.c_str(), {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                   sizeof(HeightPush), {specFloat(3, c.leakySlope)});
    });
    return {&p, kHeightKernelGroup, f32::heightInputCount(hf.kernelOctaves), padded};
  }
  const ComputePipeline& p = heightPipeline(hf, "backprop", [&] {
    return createComputePipeline(*hf.ctx, "height_backprop", {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                 sizeof(HeightPush), heightShapeConstants(hf.config));
  });
  return {&p, 64, hf.inputCount, false};
}

bool heightShaderEmbedded(const std::string& name) {
  size_t count = 0;
  const EmbeddedShader* all = embeddedShaders(&count);
  for (size_t i = 0; i < count; i++)
    if (name == all[i].name) return true;
  return false;
}

const ComputePipeline& heightWeightGradPipeline(const HeightField& hf) {
  bool atomic = hf.ctx->caps.floatAtomicAdd && !hf.forceCompareSwapAdd;
  const char* shader = atomic ? "height_weight_grad_atomic" : "height_weight_grad_cas";
  return heightPipeline(hf, shader, [&] {
    return createComputePipeline(*hf.ctx, shader, {kStorageBuffer, kStorageBuffer}, sizeof(HeightPush),
                                 heightShapeConstants(hf.config));
  });
}

const ComputePipeline& heightGenericForwardPipeline(const HeightField& hf) {
  return heightPipeline(hf, "generic", [&] {
    return createComputePipeline(*hf.ctx, "height_forward_generic", {kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                 sizeof(HeightPush), heightShapeConstants(hf.config));
  });
}

void cmdHeightForwardGeneric(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                             const Buffer& heights) {
  const ComputePipeline& p = heightGenericForwardPipeline(hf);
  uint32_t perDispatch = std::min<uint64_t>(uint64_t(hf.ctx->properties.limits.maxComputeWorkGroupCount[0]) * 64, 1u << 30);
  for (uint32_t first = 0; first < count; first += perDispatch) {
    push.first = first;
    push.count = std::min(perDispatch, count - first);
    cmdDispatch(cb, p, {bind(hf.weights), bind(points), bind(heights)}, &push, groupsFor(push.count, 64));
  }
}

}  // namespace refrax
