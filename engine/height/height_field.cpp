// Height field on the device: weights, kernel choice, forward and backward recording.
#include "engine/height/height_field.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "engine/base/error.h"
#include "engine/height/height_encoding.h"
#include "engine/height/height_field_kernels.h"
#include "engine/height/height_kernel_shapes.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {

namespace {

// Points summed by one weight-gradient invocation: long enough to keep the atomics few,
// short enough to give a GPU thousands of invocations per chunk.
constexpr uint32_t kGradientSlice = 256;
// Backward scratch budget (floats): the chunk is as many points as fit.
constexpr uint64_t kScratchFloats = uint64_t(8) << 20;
// The queued backward's dispatch table: as much as one vkCmdUpdateBuffer writes (2,048 entries,
// 409 chunks of a 3-layer network); a longer one reads the count back instead.
constexpr VkDeviceSize kBackwardGroupsBytes = 65536;

// Room for the padded kernels' inputs (kernelOctaves >= octaves).
uint64_t scratchFloatsPerPoint(const HeightFieldConfig& c, uint32_t kernelOctaves) {
  return f32::heightInputCount(kernelOctaves) + 2ull * c.hiddenLayers * c.width + 1;
}

void requireBytes(const Buffer& b, uint64_t bytes, const char* what, const char* call) {
  if (!b) fail(std::string(call) + ": the " + what + " buffer is missing");
  if (b.size < bytes)
    fail(std::string(call) + ": the " + what + " buffer holds " + std::to_string(b.size) + " bytes, " + std::to_string(bytes) +
         " are needed");
}

HeightPush basePush(const HeightField& hf) {
  HeightPush p{};
  for (int a = 0; a < 2; a++) {
    p.domainMin[a] = hf.config.domainMin[a];
    p.domainMax[a] = hf.config.domainMax[a];
  }
  p.initialHeight = hf.config.initialHeight;
  p.octaveWindow = heightOctaveWindow(hf.config);
  p.chunk = hf.backwardChunk;
  p.slice = kGradientSlice;
  return p;
}

}  // namespace

HeightField createHeightField(Context& ctx, const HeightFieldConfig& config, uint32_t seed) {
  validateHeightFieldConfig(config);
  HeightField hf;
  hf.ctx = &ctx;
  hf.config = config;
  hf.inputCount = heightInputCount(config);
  hf.parameterCount = heightParameterCount(config);
  hf.weights = createBuffer(ctx, hf.parameterCount * sizeof(float));
  std::vector<float> w = initialHeightWeights(config, seed);
  upload(ctx, hf.weights, w.data(), w.size() * sizeof(float));
  hf.kernelOctaves = heightKernelOctaves(config);
  if (hf.kernelOctaves != config.octaves) {
    HeightFieldConfig padded = config;
    padded.octaves = hf.kernelOctaves;
    hf.paddedWeights = createBuffer(ctx, heightParameterCount(padded) * sizeof(float));
  }
  uint64_t perPoint = scratchFloatsPerPoint(config, hf.kernelOctaves);
  uint64_t chunk = std::max<uint64_t>(64, std::min<uint64_t>(65536, kScratchFloats / perPoint) / 64 * 64);
  hf.backwardChunk = uint32_t(chunk);
  hf.scratch = createBuffer(ctx, chunk * perPoint * sizeof(float));
  fillBuffer(ctx, hf.scratch, 0);  // rows past a chunk's count are read (and multiplied by zero): keep them finite
  hf.backwardGroups = createBuffer(ctx, kBackwardGroupsBytes, kIndirectArgs);
  hf.pipelines = std::make_shared<HeightFieldPipelines>();
  return hf;
}

std::string HeightField::forwardKernelName() const { return heightForwardKernelName(*this); }

void cmdEvaluateHeights(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, uint32_t count, const Buffer& heights) {
  if (!hf.ctx || !hf.pipelines) fail("cmdEvaluateHeights: the height field was not created");
  if (count == 0) return;
  requireBytes(points, uint64_t(count) * 8, "points", "cmdEvaluateHeights");
  requireBytes(heights, uint64_t(count) * 4, "heights", "cmdEvaluateHeights");
  HeightPush push = basePush(hf);
  cmdHeightForward(cb, hf, push, points, count, heights);
}

uint32_t heightsQueuedGroup(const HeightField& hf) { return hf.ctx && hf.pipelines ? heightQueuedGroup(hf) : 0; }

void cmdEvaluateHeightsQueued(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& heights, const Buffer& args,
                              VkDeviceSize argsOffset, uint32_t bound) {
  if (!hf.ctx || !hf.pipelines) fail("cmdEvaluateHeightsQueued: the height field was not created");
  requireBytes(points, uint64_t(bound) * 8, "points", "cmdEvaluateHeightsQueued");
  requireBytes(heights, uint64_t(bound) * 4, "heights", "cmdEvaluateHeightsQueued");
  cmdHeightForwardQueued(cb, hf, basePush(hf), points, heights, args, argsOffset, bound);
}

namespace {

// One chunk of the backward, points [push.first, push.first + push.count): pass 1 (activations
// and deltas into the scratch), then pass 2 (the weight gradient). With `groups`, the
// dispatches take their group counts from the chunk's entries there (height_grad_groups.comp).
void cmdBackwardChunk(VkCommandBuffer cb, const HeightField& hf, const HeightBackpropKernel& backprop, const Buffer& weights,
                      const Buffer& points, const Buffer& dLossdHeight, HeightPush push, const Buffer& dLossdWeights,
                      const Buffer* groups = nullptr, VkDeviceSize groupsOffset = 0) {
  if (groups)
    cmdDispatchIndirect(cb, *backprop.pipeline, {bind(weights), bind(points), bind(dLossdHeight), bind(hf.scratch)}, &push, *groups,
                        groupsOffset + kHeightGroupEntryArgs);
  else
    cmdDispatch(cb, *backprop.pipeline, {bind(weights), bind(points), bind(dLossdHeight), bind(hf.scratch)}, &push,
                groupsFor(push.count, backprop.groupSize));
  cmdBarrier(cb);
  profileStage(cb, *hf.ctx, "height backward: activations and deltas");
  if (groups || heightGradTilesAvailable(hf)) {  // the queued backward runs on the tiles only
    cmdHeightGradTiles(cb, hf, push.count, backprop.scratchInputs, dLossdWeights, groups, groupsOffset + kHeightGroupEntryBytes);
    profileStage(cb, *hf.ctx, "height backward: weight gradient");
    return;
  }
  const ComputePipeline& grad = heightWeightGradPipeline(hf);
  const uint32_t maxGroups = hf.ctx->properties.limits.maxComputeWorkGroupCount[0];
  uint32_t slices = groupsFor(push.count, kGradientSlice);
  uint64_t perDispatch = uint64_t(maxGroups) * 64;
  for (uint64_t base = 0; base < hf.parameterCount; base += perDispatch) {
    push.weightBase = uint32_t(base);
    uint32_t n = uint32_t(std::min<uint64_t>(perDispatch, hf.parameterCount - base));
    cmdDispatch(cb, grad, {bind(hf.scratch), bind(dLossdWeights)}, &push, groupsFor(n, 64), slices);
  }
}

}  // namespace

void cmdAccumulateHeightGradients(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& dLossdHeight,
                                  uint32_t count, const Buffer& dLossdWeights) {
  if (!hf.ctx || !hf.pipelines) fail("cmdAccumulateHeightGradients: the height field was not created");
  if (count == 0) return;
  const char* call = "cmdAccumulateHeightGradients";
  requireBytes(points, uint64_t(count) * 8, "points", call);
  requireBytes(dLossdHeight, uint64_t(count) * 4, "dLossdHeight", call);
  requireBytes(dLossdWeights, hf.parameterCount * 4, "dLossdWeights", call);
  const HeightBackpropKernel backprop = heightBackpropKernel(hf);
  HeightPush push = basePush(hf);
  const Buffer& weights = backprop.padded ? cmdKernelWeights(cb, hf) : hf.weights;  // once: every chunk reads the same copy
  cmdBarrier(cb);  // earlier recorded work (a layered forward) may still use the scratch
  for (uint32_t first = 0; first < count; first += hf.backwardChunk) {
    if (first > 0) cmdBarrier(cb);  // the previous chunk's gradient pass has read the scratch
    push.first = first;
    push.count = std::min(hf.backwardChunk, count - first);
    cmdBackwardChunk(cb, hf, backprop, weights, points, dLossdHeight, push, dLossdWeights);
  }
}

bool cmdAccumulateHeightGradientsQueued(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& dLossdHeight,
                                        const Buffer& count, uint32_t bound, const Buffer& dLossdWeights) {
  if (!hf.ctx || !hf.pipelines) fail("cmdAccumulateHeightGradientsQueued: the height field was not created");
  if (!heightGradTilesAvailable(hf)) return false;  // the generic gradient pass's slices are counted on the host
  if (bound == 0) return true;
  const char* call = "cmdAccumulateHeightGradientsQueued";
  requireBytes(points, uint64_t(bound) * 8, "points", call);
  requireBytes(dLossdHeight, uint64_t(bound) * 4, "dLossdHeight", call);
  requireBytes(count, 4, "count", call);
  requireBytes(dLossdWeights, hf.parameterCount * 4, "dLossdWeights", call);
  const uint32_t layers = hf.config.hiddenLayers + 1, perChunk = 1 + layers;
  const uint32_t chunks = groupsFor(bound, hf.backwardChunk);
  const uint64_t entries = uint64_t(chunks) * perChunk;
  if (entries * kHeightGroupEntryBytes > hf.backwardGroups.size) return false;
  const HeightBackpropKernel backprop = heightBackpropKernel(hf);
  // The entries: per chunk, pass 1's groups over its points rounded up to whole tiles (pass 2
  // reads the scratch a tile at a time; rows past the count are read as zero gradients), then
  // each layer's tiles.
  std::vector<uint32_t> table(entries * 8, 0u);
  for (uint32_t c = 0; c < chunks; c++) {
    const uint32_t first = c * hf.backwardChunk, limit = std::min(hf.backwardChunk, bound - first);
    uint32_t* e = &table[size_t(c) * perChunk * 8];
    const uint32_t pass1[8] = {first, limit, kHeightGradTile, backprop.groupSize, 0, 1, 1, 1};
    std::copy(pass1, pass1 + 8, e);
    for (uint32_t l = 0; l < layers; l++) {
      const HeightGradTileGroups g = heightGradTileGroups(hf, l);
      const uint32_t tiles[8] = {first, limit, 1, kHeightGradTile, 0, g.y, g.z, 0};
      std::copy(tiles, tiles + 8, e + 8 * (l + 1));
    }
  }
  // the table's last readers (an earlier call's indirect dispatches) before it is written again
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 0, nullptr);
  vkCmdUpdateBuffer(cb, hf.backwardGroups.buffer, 0, table.size() * 4, table.data());
  cmdBarrier(cb);
  const uint32_t entryCount = uint32_t(entries);
  const ComputePipeline& groups = heightPipeline(hf, "grad groups", [&] {
    return createComputePipeline(*hf.ctx, "height_grad_groups", {kStorageBuffer, kStorageBuffer, kStorageBuffer}, 4);
  });
  cmdDispatch(cb, groups, {bind(count), bind(hf.backwardGroups), bind(dLossdHeight)}, &entryCount, groupsFor(entryCount, 64));
  HeightPush push = basePush(hf);
  const Buffer& weights = backprop.padded ? cmdKernelWeights(cb, hf) : hf.weights;
  cmdBarrier(cb);  // the group counts, the zeroed rows; earlier recorded work may still use the scratch
  for (uint32_t c = 0; c < chunks; c++) {
    if (c > 0) cmdBarrier(cb);
    push.first = c * hf.backwardChunk;
    push.count = std::min(hf.backwardChunk, bound - push.first);
    cmdBackwardChunk(cb, hf, backprop, weights, points, dLossdHeight, push, dLossdWeights, &hf.backwardGroups,
                     VkDeviceSize(c) * perChunk * kHeightGroupEntryBytes);
  }
  return true;
}

double warmUpHeightField(HeightField& hf) {
  if (!hf.ctx || !hf.pipelines) fail("warmUpHeightField: the height field was not created");
  // lavapipe compiles a pipeline at its first dispatch, not at creation: dispatch both
  // directions once on one point (into throw-away buffers).
  auto t0 = std::chrono::steady_clock::now();
  Context& ctx = *hf.ctx;
  const HeightFieldConfig& c = hf.config;
  std::vector<float> point = {0.5f * (c.domainMin[0] + c.domainMax[0]), 0.5f * (c.domainMin[1] + c.domainMax[1])};
  Buffer pb = createBufferFrom(ctx, point), hb = createBuffer(ctx, 4), gb = createBuffer(ctx, hf.parameterCount * 4);
  fillBuffer(ctx, gb, 0);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdEvaluateHeights(cb, hf, pb, 1, hb);
    cmdBarrier(cb);
    cmdAccumulateHeightGradients(cb, hf, pb, hb, 1, gb);
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<float> downloadWeights(Context& ctx, const HeightField& hf) {
  return downloadVector<float>(ctx, hf.weights, hf.parameterCount);
}

void uploadWeights(Context& ctx, HeightField& hf, const std::vector<float>& weights) {
  if (weights.size() != hf.parameterCount)
    fail("uploadWeights: " + std::to_string(weights.size()) + " weights given, the height field has " +
         std::to_string(hf.parameterCount));
  upload(ctx, hf.weights, weights.data(), weights.size() * sizeof(float));
}

void scaleHeightField(Context& ctx, HeightField& hf, double level, double scale) {
  std::vector<float> w = downloadWeights(ctx, hf);
  for (size_t k = w.size() - hf.config.width; k < w.size(); k++) w[k] = float(scale * w[k]);  // the output layer: the last `width` floats
  uploadWeights(ctx, hf, w);
  hf.config.initialHeight = float(level + scale * (double(hf.config.initialHeight) - level));
}

void mirrorHeightField(Context& ctx, HeightField& hf, double level) { scaleHeightField(ctx, hf, level, -1.0); }

}  // namespace refrax
