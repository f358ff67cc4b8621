// Height field forward: picks the kernel for the configuration (generated straight-line
// kernels where the build has them and the device's limits allow, the loop-based one
// otherwise) and records it.
#include <algorithm>
#include <cstring>

#include "engine/base/error.h"
#include "engine/height/height_encoding.h"
#include "engine/height/height_field_kernels.h"
#include "engine/height/height_kernel_shapes.h"
#include "engine/vk/shader_table.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

enum class ForwardForm { Generic, Fused, Layered };

// Points per layered chunk: two [width][points] activation regions in the scratch, whole workgroups.
uint32_t layeredChunk(const HeightField& hf) {
  uint64_t floats = hf.scratch.size / 4;
  return uint32_t(std::min<uint64_t>(floats / (2ull * hf.config.width), 1u << 20) / kHeightKernelGroup * kHeightKernelGroup);
}

ForwardForm forwardForm(const HeightField& hf) {
  const HeightFieldConfig& c = hf.config;
  const VkPhysicalDeviceLimits& limits = hf.ctx->properties.limits;
  bool fits = limits.maxComputeWorkGroupInvocations >= kHeightKernelGroup && limits.maxComputeWorkGroupSize[0] >= kHeightKernelGroup &&
              limits.maxComputeSharedMemorySize >= kHeightStageFloats * 4;
  if (hf.forceGenericForward || !fits) return ForwardForm::Generic;
  if (c.width <= kHeightFusedMaxWidth && heightShaderEmbedded(heightFusedKernelName(c.width, c.hiddenLayers, hf.kernelOctaves)))
    return ForwardForm::Fused;
  if (heightShaderEmbedded(heightLayerFirstKernelName(c.width, hf.kernelOctaves)) && heightShaderEmbedded(heightLayerHiddenKernelName(c.width)) &&
      heightShaderEmbedded(heightLayerLastKernelName(c.width)) && layeredChunk(hf) > 0)
    return ForwardForm::Layered;
  return ForwardForm::Generic;
}

const ComputePipeline& generatedPipeline(const HeightField& hf, const std::string& name, uint32_t buffers) {
  return heightPipeline(hf, name, [&] {
    return createComputePipeline(*hf.ctx, name.c_str(), storageBuffers(buffers), sizeof(HeightPush),
                                  {specFloat(3, hf.config.leakySlope)});
  });
}

const ComputePipeline& fusedPipeline(const HeightField& hf) {
  const HeightFieldConfig& c = hf.config;
  return generatedPipeline(hf, heightFusedKernelName(c.width, c.hiddenLayers, hf.kernelOctaves), 3);
}
const ComputePipeline& firstPipeline(const HeightField& hf) {
  return generatedPipeline(hf, heightLayerFirstKernelName(hf.config.width, hf.kernelOctaves), 3);
}
const ComputePipeline& hiddenPipeline(const HeightField& hf) { return generatedPipeline(hf, heightLayerHiddenKernelName(hf.config.width), 2); }
const ComputePipeline& lastPipeline(const HeightField& hf) { return generatedPipeline(hf, heightLayerLastKernelName(hf.config.width), 4); }

uint32_t maxPointsPerDispatch(const HeightField& hf, uint32_t group) {
  return uint32_t(std::min<uint64_t>(uint64_t(hf.ctx->properties.limits.maxComputeWorkGroupCount[0]) * group, 1u << 30));
}

void cmdFused(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count, const Buffer& heights) {
  const ComputePipeline& p = fusedPipeline(hf);
  const Buffer& weights = cmdKernelWeights(cb, hf);
  uint32_t perDispatch = maxPointsPerDispatch(hf, kHeightKernelGroup);
  for (uint32_t first = 0; first < count; first += perDispatch) {
    push.first = first;
    push.count = std::min(perDispatch, count - first);
    cmdDispatch(cb, p, {bind(weights), bind(points), bind(heights)}, &push, groupsFor(push.count, kHeightKernelGroup));
  }
}

// Layer by layer through two activation regions of the scratch, a chunk of points at a time.
void cmdLayered(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count, const Buffer& heights) {
  const HeightFieldConfig& c = hf.config;
  const uint32_t W = c.width, I = f32::heightInputCount(hf.kernelOctaves), G = heightLayerGroupOutputs(W), chunk = layeredChunk(hf);
  const ComputePipeline &first = firstPipeline(hf), &hidden = hiddenPipeline(hf), &last = lastPipeline(hf);
  push.chunk = chunk;
  const Buffer& weights = cmdKernelWeights(cb, hf);
  cmdBarrier(cb);  // earlier recorded work may still read the scratch
  for (uint32_t start = 0; start < count; start += chunk) {
    if (start > 0) cmdBarrier(cb);
    push.first = start;
    push.count = std::min(chunk, count - start);
    uint32_t groups = groupsFor(push.count, kHeightKernelGroup);
    uint32_t in = 0, out = W * chunk;
    for (uint32_t j0 = 0; j0 < W; j0 += G) {
      push.weightBase = j0 * I;
      push.outOffset = j0 * chunk;
      cmdDispatch(cb, first, {bind(weights), bind(points), bind(hf.scratch)}, &push, groups);
    }
    for (uint32_t l = 1; l < c.hiddenLayers; l++) {
      cmdBarrier(cb);
      uint32_t layerBase = W * I + (l - 1) * W * W;
      for (uint32_t j0 = 0; j0 < W; j0 += G) {
        push.weightBase = layerBase + j0 * W;
        push.inOffset = in;
        push.outOffset = out + j0 * chunk;
        cmdDispatch(cb, hidden, {bind(weights), bind(hf.scratch)}, &push, groups);
      }
      std::swap(in, out);
    }
    cmdBarrier(cb);
    push.weightBase = W * I + (c.hiddenLayers - 1) * W * W;
    push.inOffset = in;
    cmdDispatch(cb, last, {bind(weights), bind(points), bind(hf.scratch), bind(heights)}, &push, groups);
  }
}

struct PadPush {  // mirror of height_pad_weights.comp
  uint32_t count, width, inputs, paddedInputs;
};

}  // namespace

uint32_t heightKernelOctaves(const HeightFieldConfig& c) {
  // Straight-line kernels exist for a few octave counts: the smallest at or above the network's.
  for (uint32_t o = c.octaves; o <= c.octaves + 8; o++) {
    if (c.width <= kHeightFusedMaxWidth && heightShaderEmbedded(heightFusedKernelName(c.width, c.hiddenLayers, o)) &&
        heightShaderEmbedded(heightBackpropKernelName(c.width, c.hiddenLayers, o)))
      return o;
    if (c.width > kHeightFusedMaxWidth && heightShaderEmbedded(heightLayerFirstKernelName(c.width, o))) return o;
  }
  return c.octaves;
}

const Buffer& cmdKernelWeights(VkCommandBuffer cb, const HeightField& hf) {
  if (hf.kernelOctaves == hf.config.octaves) return hf.weights;
  const ComputePipeline& p = heightPipeline(hf, "pad", [&] {
    return createComputePipeline(*hf.ctx, "height_pad_weights", {kStorageBuffer, kStorageBuffer}, sizeof(PadPush));
  });
  PadPush push{uint32_t(hf.paddedWeights.size / 4), hf.config.width, hf.inputCount, f32::heightInputCount(hf.kernelOctaves)};
  cmdBarrier(cb);  // earlier recorded work may still read the padded copy, or write the weights
  cmdDispatch(cb, p, {bind(hf.weights), bind(hf.paddedWeights)}, &push, groupsFor(push.count, 64));
  cmdBarrier(cb);
  return hf.paddedWeights;
}

std::string heightForwardKernelName(const HeightField& hf) {
  const HeightFieldConfig& c = hf.config;
  switch (forwardForm(hf)) {
    case ForwardForm::Fused: return heightFusedKernelName(c.width, c.hiddenLayers, hf.kernelOctaves);
    case ForwardForm::Layered: return "height_layer_*_w" + std::to_string(c.width);
    default: return "height_forward_generic";
  }
}

void cmdHeightForward(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                      const Buffer& heights) {
  switch (forwardForm(hf)) {
    case ForwardForm::Fused: cmdFused(cb, hf, push, points, count, heights); break;
    case ForwardForm::Layered: cmdLayered(cb, hf, push, points, count, heights); break;
    default: cmdHeightForwardGeneric(cb, hf, push, points, count, heights);
  }
}

uint32_t heightQueuedGroup(const HeightField& hf) {
  switch (forwardForm(hf)) {
    case ForwardForm::Fused: return kHeightKernelGroup;
    case ForwardForm::Layered: return 0;  // its chunks are counted on the host
    default: return 64;
  }
}

void cmdHeightForwardQueued(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, const Buffer& heights,
                            const Buffer& args, VkDeviceSize offset, uint32_t bound) {
  push.first = 0;
  push.count = bound;
  switch (forwardForm(hf)) {
    case ForwardForm::Fused: {
      const ComputePipeline& p = fusedPipeline(hf);
      const Buffer& weights = cmdKernelWeights(cb, hf);
      cmdDispatchIndirect(cb, p, {bind(weights), bind(points), bind(heights)}, &push, args, offset);
      break;
    }
    case ForwardForm::Layered: fail("the layered height forward cannot run on a count the device wrote");
    default:
      cmdDispatchIndirect(cb, heightGenericForwardPipeline(hf), {bind(hf.weights), bind(points), bind(heights)}, &push, args, offset);
  }
}

}  // namespace refrax
