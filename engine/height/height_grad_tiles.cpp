// Backward pass 2 by the generated weight-gradient tiles: per layer l, dW_l += D_l^T X_l over
// the chunk, one dispatch of (point tiles, input blocks, output blocks).
#include "engine/base/error.h"
#include "engine/height/height_field_kernels.h"
#include "engine/height/height_kernel_shapes.h"
#include "engine/vk/shader_table.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

struct GradPush {  // mirror of the push block in the generated height_grad_tile_* kernels
  uint32_t count, n, m, xBase, dBase, weightBase, xStride;
};

bool atomicAdds(const HeightField& hf) { return hf.ctx->caps.floatAtomicAdd && !hf.forceCompareSwapAdd; }

std::vector<uint32_t> blocksUsed(const HeightField& hf) {
  return {heightGradBlock(hf.config.width), heightGradBlock(1)};
}

const ComputePipeline& tilePipeline(const HeightField& hf, uint32_t mb) {
  std::string name = heightGradKernelName(mb, atomicAdds(hf));
  return heightPipeline(hf, name, [&] {
    return createComputePipeline(*hf.ctx, name.c_str(), {kStorageBuffer, kStorageBuffer}, sizeof(GradPush));
  });
}

}  // namespace

bool heightGradTilesAvailable(const HeightField& hf) {
  const VkPhysicalDeviceLimits& limits = hf.ctx->properties.limits;
  if (hf.forceGenericBackward) return false;
  for (uint32_t mb : blocksUsed(hf)) {
    if (!heightShaderEmbedded(heightGradKernelName(mb, atomicAdds(hf)))) return false;
    if (limits.maxComputeSharedMemorySize < kHeightGradTile * mb * 4 || limits.maxComputeWorkGroupCount[2] < hf.config.width / mb)
      return false;
  }
  return true;
}

HeightGradTileGroups heightGradTileGroups(const HeightField& hf, uint32_t layer) {
  const HeightFieldConfig& c = hf.config;
  const uint32_t n = uint32_t(layer == 0 ? hf.inputCount : c.width), m = uint32_t(layer == c.hiddenLayers ? 1 : c.width);
  return {groupsFor(n, kHeightGradLanes), m / heightGradBlock(m)};
}

void cmdHeightGradTiles(VkCommandBuffer cb, const HeightField& hf, uint32_t count, uint32_t scratchInputs, const Buffer& dLossdWeights,
                        const Buffer* groups, VkDeviceSize groupsOffset) {
  const HeightFieldConfig& c = hf.config;
  // I: the network's inputs (the weights' layout); S: the inputs per point in the scratch
  // (more than I after a padded pass 1, whose extra inputs have no weights to train)
  const uint64_t C = hf.backwardChunk, W = c.width, I = hf.inputCount, S = scratchInputs;
  const uint32_t tiles = groupsFor(count, kHeightGradTile);
  // Scratch offsets as in shaders/include/height_shape.glsl.
  auto scratchX = [&](uint32_t l) { return C * (l == 0 ? 0 : S + (l - 1) * W); };
  auto scratchD = [&](uint32_t l) { return C * (S + c.hiddenLayers * W + l * W); };
  for (uint32_t l = 0; l <= c.hiddenLayers; l++) {
    uint32_t n = uint32_t(l == 0 ? I : W), m = uint32_t(l == c.hiddenLayers ? 1 : W);
    uint32_t mb = heightGradBlock(m);
    GradPush push{count, n, m, uint32_t(scratchX(l)), uint32_t(scratchD(l)),
                  uint32_t(l == 0 ? 0 : W * I + uint64_t(l - 1) * W * W), uint32_t(l == 0 ? S : n)};
    const HeightGradTileGroups g = heightGradTileGroups(hf, l);
    if (groups)
      cmdDispatchIndirect(cb, tilePipeline(hf, mb), {bind(hf.scratch), bind(dLossdWeights)}, &push, *groups,
                          groupsOffset + l * kHeightGroupEntryBytes + kHeightGroupEntryArgs);
    else
      cmdDispatch(cb, tilePipeline(hf, mb), {bind(hf.scratch), bind(dLossdWeights)}, &push, tiles, g.y, g.z);
  }
}

}  // namespace refrax
