#pragma once
// The training losses on the device, each with its gradient:
//   image loss   L = 0.8 * L1 + 0.2 * (1 - SSIM)   (SSIM as in shaders/include/image_loss.glsl:
//                11x11 Gaussian window, sigma 1.5, per channel, zero padding as 3DGS, mean over
//                every pixel and channel)  ->  dL/d(rendered) per element;
//   density      R = weight * mean(sigmoid(logit)^2)  (weight 0.007)  ->  added to dL/dlogit.
// Images are float buffers, row-major, channel-interleaved (pixel * channels + channel),
// values nominally in [0, 1]. Each loss also leaves a vec4 result on the device:
//   image loss: {L, sum |x - y|, sum SSIM map, 0};  density: {R, sum sigmoid^2, 0, 0}.
#include <cstdint>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;
struct GpuTimer;

constexpr float kDensityRegularizerWeight = 0.007f;

struct LossPipelines {
  ComputePipeline moments;   // pass 1: horizontal window sums of x, y, x^2, y^2, xy
  ComputePipeline ssim;      // pass 2: vertical sums, SSIM map, its slopes, |x - y|
  ComputePipeline sum;       // partial sums of the SSIM map and |x - y|
  ComputePipeline slopes;    // pass 3: horizontal sums of the slopes
  ComputePipeline grad;      // pass 4: vertical sums, dL/dx
  ComputePipeline reduce;    // partial sums -> result vec4
  ComputePipeline density;   // density regulariser
};
LossPipelines createLossPipelines(Context& ctx);

// Scratch for one image size (11 floats per element plus one vec2 per 64).
struct ImageLossScratch {
  uint32_t width = 0, height = 0, channels = 0;
  Buffer moments;   // vec4 (x, y, x^2, y^2) window sums; reused for the blurred slopes
  Buffer cross;     // float xy window sums
  Buffer slopes;    // vec4 (dS/dmu1, dS/dexx, dS/dexy, 0)
  Buffer terms;     // vec2 (|x - y|, SSIM map) to be summed
  Buffer partials;  // vec2 per 64 elements
};
// (Re)allocates when the size differs; a no-op otherwise.
void prepareImageLossScratch(Context& ctx, ImageLossScratch& scratch, uint32_t width, uint32_t height, uint32_t channels);

// Records the four passes and the reduction (with barriers between them, and one before
// the first, so the inputs may come from the previous dispatch). `grad` receives
// dL/d(rendered) (width * height * channels floats), `result` the vec4 described above.
// With a timer (started by the caller), each pass is stamped. Buffers too small for the
// scratch's image size are refused (refrax::Error) before anything is recorded.
void cmdImageLoss(VkCommandBuffer cb, const LossPipelines& p, const ImageLossScratch& scratch, const Buffer& rendered,
                  const Buffer& target, const Buffer& grad, const Buffer& result, GpuTimer* timer = nullptr);

// Workgroups' partial sums the density regulariser needs for `count` logits (vec2 each).
uint32_t densityPartialCount(uint32_t count);
// Records the regulariser: gradLogits[i] += weight / count * d(sigmoid^2)/dlogit, result
// as described above, logit i (and its gradient) at element i * stride + offset (training:
// the Gaussian table's density logits and their gradients in place). `partials` holds
// densityPartialCount(count) vec2. Nothing for count 0. Buffers too small for the sizes given
// are refused (refrax::Error) before recording.
void cmdDensityRegularizer(VkCommandBuffer cb, const LossPipelines& p, const Buffer& logits, uint32_t count,
                           const Buffer& gradLogits, const Buffer& partials, const Buffer& result,
                           float weight = kDensityRegularizerWeight, uint32_t stride = 1, uint32_t offset = 0);

}  // namespace refrax
