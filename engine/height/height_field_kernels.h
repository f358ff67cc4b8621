#pragma once
// Internal to the height field: push constants, the lazily created pipelines, and the
// forward kernel choice (generated straight-line kernels where the build has one for the
// configuration, the loop-based one otherwise).
#include <functional>
#include <map>
#include <string>

#include "engine/height/height_field.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

// Mirror of shaders/include/height_push.glsl.
struct HeightPush {
  float domainMin[2];
  float domainMax[2];
  uint32_t count;
  uint32_t first;
  uint32_t chunk;
  uint32_t slice;
  float initialHeight;
  uint32_t weightBase;
  uint32_t inOffset;
  uint32_t outOffset;
  float octaveWindow;
};
static_assert(sizeof(HeightPush) == 52, "HeightPush must match height_push.glsl");

struct HeightFieldPipelines {
  std::map<std::string, ComputePipeline> byName;  // created on first use, kept for the field's life
};

// Name of the forward kernel the field uses with its current settings (creates nothing).
std::string heightForwardKernelName(const HeightField& hf);
// Records the forward for points [0, count) (push.first/count are set here).
void cmdHeightForward(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                      const Buffer& heights);

// The forward over points [0, n) for an n the device wrote: one indirect dispatch whose group
// counts lie at args + offset, in groups of heightQueuedGroup(hf) points; push.count = bound
// (>= n) keeps the last group's spare lanes inside the buffers. Not for the layered form.
uint32_t heightQueuedGroup(const HeightField& hf);  // 0: the current form cannot
void cmdHeightForwardQueued(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, const Buffer& heights,
                            const Buffer& args, VkDeviceSize offset, uint32_t bound);

// The octave count of the generated kernels that serve a network of c.octaves (c.octaves
// itself where none is embedded at or above it): see "padded kernels" in height_field.h.
uint32_t heightKernelOctaves(const HeightFieldConfig& c);
// The weights the generated kernels read: hf.weights, or (recorded here, between barriers)
// their padded copy when the kernels have more octaves than the network.
const Buffer& cmdKernelWeights(VkCommandBuffer cb, const HeightField& hf);

// The loop-based forward (any shape).
const ComputePipeline& heightGenericForwardPipeline(const HeightField& hf);
void cmdHeightForwardGeneric(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                             const Buffer& heights);

// Backward pass 1: the generated fused kernel where there is one, else the loop-based one.
struct HeightBackpropKernel {
  const ComputePipeline* pipeline;
  uint32_t groupSize;
  uint32_t scratchInputs;  // encoding inputs per point it stores in the scratch (the padded count for padded kernels)
  bool padded;             // it reads the padded weights (cmdKernelWeights)
};
HeightBackpropKernel heightBackpropKernel(const HeightField& hf);
bool heightShaderEmbedded(const std::string& name);
const ComputePipeline& heightWeightGradPipeline(const HeightField& hf);

// Backward pass 2 by generated weight-gradient tiles (when the build has them and the device
// allows): one dispatch per layer over the chunk's `count` points in the scratch, of
// (tiles of kHeightGradTile points, y, z) groups. With `groups`, layer l's group counts are
// the entry at groupsOffset + l * kHeightGroupEntryBytes (height_grad_groups.comp: the tiles
// that hold a count the device wrote).
bool heightGradTilesAvailable(const HeightField& hf);
struct HeightGradTileGroups {
  uint32_t y, z;
};
HeightGradTileGroups heightGradTileGroups(const HeightField& hf, uint32_t layer);
void cmdHeightGradTiles(VkCommandBuffer cb, const HeightField& hf, uint32_t count, uint32_t scratchInputs, const Buffer& dLossdWeights,
                        const Buffer* groups = nullptr, VkDeviceSize groupsOffset = 0);
// height_grad_groups.comp's entries: 8 uints, {first, limit, roundTo, groupSize, x, y, z, 0};
// the VkDispatchIndirectCommand at byte 16.
constexpr VkDeviceSize kHeightGroupEntryBytes = 32;
constexpr VkDeviceSize kHeightGroupEntryArgs = 16;

// The pipeline `key` of the field, created by `make` on first use.
const ComputePipeline& heightPipeline(const HeightField& hf, const std::string& key, const std::function<ComputePipeline()>& make);
// Specialization constants of the loop-based shaders (height_shape.glsl).
std::vector<SpecConstant> heightShapeConstants(const HeightFieldConfig& c);

}  // namespace refrax
