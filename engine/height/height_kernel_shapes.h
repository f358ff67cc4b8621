#pragma once
// Shapes of the generated straight-line height-field kernels, shared by their build-time
// generator (shaders/height/generate_height_kernels.cpp) and the engine that dispatches them.
//
// Why generated: on lavapipe a load inside any loop or branch becomes eight one-lane loads
// with bounds checks, so MLP kernels with loops run at 1-3 GFLOP/s; straight-line code
// (weights staged in shared memory, read at constant offsets, activations in named locals)
// runs 10-20x faster (docs/method.md §1.7). The code depends on the shape, so it is generated at
// build time for the shapes listed in cmake/HeightKernels.cmake; other shapes use the
// loop-based kernels.
//
// Two forms:
//  fused   (width <= kHeightFusedMaxWidth): the whole network in one dispatch, per (width,
//          hiddenLayers, octaves); also backward pass 1 (activations and deltas).
//  layered (wider): one dispatch per layer and group of heightLayerGroupOutputs(width)
//          output neurons, activations through the scratch buffer ([neuron][point], chunks
//          of points); kernels per (width, octaves) for the first layer, per width for the
//          hidden and output layers.
#include <algorithm>
#include <cstdint>
#include <string>

namespace refrax {

constexpr uint32_t kHeightKernelGroup = 256;     // invocations per workgroup (one point each)
constexpr uint32_t kHeightStageFloats = 8192;    // weights staged in shared memory at once (32 KB)
constexpr uint32_t kHeightFusedMaxWidth = 64;

// Weight-gradient tiles (backward pass 2): points per workgroup and lanes (inputs k) per
// workgroup; kernels exist per outputs-per-block mb (kHeightGradBlocks), chosen as the largest
// listed mb that divides the layer's output count. 128 points per tile: measured on lavapipe
// (`refrax bench mlp --widths 64 --depth 3`, 16k points) 53-56 ms per backward against 68 ms
// with 32 points and 61 ms with 256 (whose first compile took over a minute); fewer points per
// block of outputs (mb 8) or one block of all 64 were slower (90, 88 ms).
constexpr uint32_t kHeightGradTile = 128;
constexpr uint32_t kHeightGradLanes = 32;
constexpr uint32_t kHeightGradBlocks[] = {32, 16, 1};
inline uint32_t heightGradBlock(uint32_t outputs) {
  for (uint32_t mb : kHeightGradBlocks)
    if (outputs % mb == 0) return mb;
  return 1;
}
inline std::string heightGradKernelName(uint32_t mb, bool atomic) {
  return "height_grad_tile_mb" + std::to_string(mb) + (atomic ? "_atomic" : "_cas");
}

// Output neurons of one layered dispatch: as many rows of `width` weights as fit the stage.
inline uint32_t heightLayerGroupOutputs(uint32_t width) { return std::max(4u, std::min(width, kHeightStageFloats / width) / 4 * 4); }

inline std::string heightFusedKernelName(uint32_t width, uint32_t hidden, uint32_t octaves) {
  return "height_fused_w" + std::to_string(width) + "_d" + std::to_string(hidden) + "_l" + std::to_string(octaves);
}
inline std::string heightBackpropKernelName(uint32_t width, uint32_t hidden, uint32_t octaves) {
  return "height_backprop_w" + std::to_string(width) + "_d" + std::to_string(hidden) + "_l" + std::to_string(octaves);
}
inline std::string heightLayerFirstKernelName(uint32_t width, uint32_t octaves) {
  return "height_layer_first_w" + std::to_string(width) + "_l" + std::to_string(octaves);
}
inline std::string heightLayerHiddenKernelName(uint32_t width) { return "height_layer_hidden_w" + std::to_string(width); }
inline std::string heightLayerLastKernelName(uint32_t width) { return "height_layer_last_w" + std::to_string(width); }

}  // namespace refrax
