#pragma once
// The water surface z = H(x, y): an MLP on a NeRF frequency encoding of (x, y) (paper §3.2,
// docs/method.md §1.1), evaluated and differentiated on the device, with a CPU double reference.
//
// Model. (x, y) is mapped from [domainMin, domainMax] to u in [-1,1]^2 and encoded into
// 2 + 4*octaves inputs (shaders/include/height_encoding.glsl gives the exact order).
// Then `hiddenLayers` layers of `width` neurons, Leaky ReLU (leakySlope), no biases, and one
// linear output; H = output + initialHeight.
//
// Weight layout (one float buffer, all layers concatenated, each row-major [out][in]):
//   layer 0:                width x inputs          (inputs = 2 + 4*octaves)
//   layers 1..hidden-1:     width x width
//   output layer:           1 x width
//   parameterCount = width*inputs + (hiddenLayers-1)*width^2 + width.
//
// Initialisation (seeded, the same on every platform: mt19937 words, 24-bit uniforms):
// hidden layers Kaiming-uniform for Leaky ReLU, U(-b, b) with b = sqrt(6 / ((1 + slope^2) *
// fan_in)) (torch.nn.init.kaiming_uniform_(a=slope, nonlinearity='leaky_relu')); the output
// layer U(-lastLayerInitRange, lastLayerInitRange).
//
// Bad input policy: a point whose x or y is not finite gets a NaN height and contributes
// nothing to the weight gradients; so does a point whose dLoss/dHeight is not finite.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct HeightFieldConfig {
  uint32_t octaves = 6, width = 256, hiddenLayers = 6;
  float leakySlope = 0.01f, lastLayerInitRange = 0.1f, initialHeight = 0.0f;
  float domainMin[2] = {-1, -1}, domainMax[2] = {1, 1};  // world xy mapped to [-1,1]^2 before encoding
  // Coarse-to-fine encoding window as a fraction of the octaves, in [0, 1]: the window
  // a = encodingWindow * octaves of height_encoding.glsl; 1 opens every octave (the plain
  // NeRF encoding). Training opens it gradually; it is saved with the weights.
  float encodingWindow = 1.0f;
};
// The window a of height_encoding.glsl for this configuration.
inline float heightOctaveWindow(const HeightFieldConfig& c) { return c.encodingWindow * float(c.octaves); }

uint32_t heightInputCount(const HeightFieldConfig& config);
uint64_t heightParameterCount(const HeightFieldConfig& config);
// Throws refrax::Error naming the first bad field (zero sizes, non-finite values, empty domain).
void validateHeightFieldConfig(const HeightFieldConfig& config);

// Compute pipelines of one HeightField, created on first use (lavapipe JIT-compiles each
// one when it is created: seconds to a minute for the generated straight-line shaders).
struct HeightFieldPipelines;

struct HeightField {
  Context* ctx = nullptr;
  HeightFieldConfig config;
  uint32_t inputCount = 0;
  uint64_t parameterCount = 0;
  Buffer weights;  // parameterCount floats, layout above
  // Padded kernels. The build generates straight-line kernels for a few octave counts only
  // (cmake/HeightKernels.cmake); a network of fewer octaves than one of them runs on that
  // one's kernels (kernelOctaves), on a copy of its weights whose first layer is widened with
  // zero columns (paddedWeights, made before each forward and backward). The extra encoding
  // inputs are silenced by the coarse-to-fine window too, whose a <= octaves closes every
  // octave from `octaves` up. Why: the loop-based kernels run 10-20x slower on lavapipe, and
  // the data's size (engine/train/model_sizing.h) picks any octave count.
  uint32_t kernelOctaves = 0;  // == config.octaves when the kernels fit the network as it is
  Buffer paddedWeights;        // present when kernelOctaves > config.octaves
  // Backward scratch: per point, every layer's input and every layer's output delta, for
  // backwardChunk points at a time (the weight gradient is then one GEMM per layer); the
  // layered forward reuses it. backwardChunk may be lowered (tests), never raised.
  Buffer scratch;
  uint32_t backwardChunk = 0;
  // cmdAccumulateHeightGradientsQueued's dispatch table (height_grad_groups.comp).
  Buffer backwardGroups;
  // Kernel choice, for tests and benchmarks: the loop-based kernels instead of the generated
  // straight-line ones; the compare-and-swap float add even where atomicAdd exists.
  bool forceGenericForward = false;
  bool forceGenericBackward = false;  // the loop-based weight-gradient pass instead of the generated tiles
  bool forceCompareSwapAdd = false;
  std::shared_ptr<HeightFieldPipelines> pipelines;

  // Which forward kernel cmdEvaluateHeights uses now ("generic", "fused W<w> D<d> L<l>", ...).
  std::string forwardKernelName() const;
};

HeightField createHeightField(Context& ctx, const HeightFieldConfig& config, uint32_t seed);
// heights[i] = H(points[i]); points: float2 (x, y) world coordinates; heights: float
void cmdEvaluateHeights(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, uint32_t count, const Buffer& heights);
// The same for the points [0, n) of a count the device wrote (HeightSource::evaluateQueued);
// heightsQueuedGroup is 0 where the field's forward form cannot run so.
uint32_t heightsQueuedGroup(const HeightField& hf);
void cmdEvaluateHeightsQueued(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& heights, const Buffer& args,
                              VkDeviceSize argsOffset, uint32_t bound);
// dLossdWeights[j] += sum_i dLossdHeight[i] * dH(points[i])/dweight_j   (accumulates, never overwrites)
void cmdAccumulateHeightGradients(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& dLossdHeight,
                                  uint32_t count, const Buffer& dLossdWeights);
// The same for the points [0, n) of a count the device wrote (count[0]; HeightSource::
// accumulateQueued): the chunks that bound >= n points need are recorded, and each one's
// dispatches take their group counts from a table the device fills from n, so the host never
// reads n. Rows of dLossdHeight past n (up to a weight-gradient tile) are set to zero: they
// are read as part of n's last tile. Returns false, recording nothing, where the field cannot
// run so (the loop-based weight-gradient pass, or more chunks than the table holds).
bool cmdAccumulateHeightGradientsQueued(VkCommandBuffer cb, const HeightField& hf, const Buffer& points, const Buffer& dLossdHeight,
                                        const Buffer& count, uint32_t bound, const Buffer& dLossdWeights);
// Creates and runs once every pipeline the current kernel choice needs, so that the compile
// cost (lavapipe JIT-compiles at the first dispatch) is paid here; returns the milliseconds.
double warmUpHeightField(HeightField& hf);

std::vector<float> downloadWeights(Context& ctx, const HeightField& hf);
void uploadWeights(Context& ctx, HeightField& hf, const std::vector<float>& weights);  // size must match
// The relief scaled about the level z = `level`: H'(x, y) = level + scale (H(x, y) - level) up
// to float rounding (the output layer is linear and has no bias: its weights scaled, initialHeight
// moved). Why: the Gaussians absorb a water learned at part of its height, the views' plane
// sweep does not (docs/experiments/2026-12-05-water-valley.md); training can compare heights.
void scaleHeightField(Context& ctx, HeightField& hf, double level, double scale);
// The mirror image about the level (scale -1). Why: waves learned upside down fit the views
// almost as well as the right ones (docs/experiments/2026-11-28-upside-down-water.md).
void mirrorHeightField(Context& ctx, HeightField& hf, double level);

// File format (little-endian), written atomically (temp file + rename):
//   char[8] "RFXHGTF\0", u32 version (1), u32 octaves, width, hiddenLayers,
//   f32 leakySlope, lastLayerInitRange, initialHeight, domainMin[2], domainMax[2],
//   u64 parameterCount, f32 weights[parameterCount], u32 FNV-1a checksum of every byte before it.
void saveHeightField(const std::string& path, Context& ctx, const HeightField& hf);
HeightField loadHeightField(Context& ctx, const std::string& path);  // refrax::Error on missing/truncated/corrupt files

// The initial weights createHeightField uploads for `seed`.
std::vector<float> initialHeightWeights(const HeightFieldConfig& config, uint32_t seed);

}  // namespace refrax
