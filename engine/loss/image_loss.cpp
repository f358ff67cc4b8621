#include "engine/loss/image_loss.h"

#include "engine/base/error.h"
#include "engine/base/shared_math.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"

namespace refrax::f32 {
#include "image_loss.glsl"
}

namespace refrax {
namespace {

constexpr uint32_t kGroup = 256;  // local size of density_regularizer

struct ImagePush {
  uint32_t width, height, channels, count;
  float window[12];  // the SSIM window's 11 taps (and one pad)
};
constexpr uint32_t kBlockOutputs = 8;  // kBlock of image_loss_pass.glsl
constexpr uint32_t kSumChunk = 64;  // elements per invocation of sum_pairs
struct ReducePush {
  uint32_t count;
  float scaleX, scaleY, bias;
};
struct DensityPush {
  uint32_t count;
  float scale;
  uint32_t stride, offset;
};

}  // namespace

LossPipelines createLossPipelines(Context& ctx) {
  LossPipelines p;
  p.moments = createComputePipeline(ctx, "image_loss_moments", {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                    sizeof(ImagePush));
  p.ssim = createComputePipeline(ctx, "image_loss_ssim",
                                 {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                 sizeof(ImagePush));
  p.sum = createComputePipeline(ctx, "sum_pairs", {kStorageBuffer, kStorageBuffer}, sizeof(uint32_t));
  p.slopes = createComputePipeline(ctx, "image_loss_slopes", {kStorageBuffer, kStorageBuffer}, sizeof(ImagePush));
  p.grad = createComputePipeline(ctx, "image_loss_grad", {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer}, sizeof(ImagePush));
  p.reduce = createComputePipeline(ctx, "reduce_sums", {kStorageBuffer, kStorageBuffer}, sizeof(ReducePush));
  p.density = createComputePipeline(ctx, "density_regularizer", {kStorageBuffer, kStorageBuffer, kStorageBuffer}, sizeof(DensityPush));
  return p;
}

void prepareImageLossScratch(Context& ctx, ImageLossScratch& s, uint32_t width, uint32_t height, uint32_t channels) {
  if (width == 0 || height == 0 || channels == 0) fail("image loss: empty image (" + std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) + ")");
  if (s.moments && s.width == width && s.height == height && s.channels == channels) return;
  VkDeviceSize count = VkDeviceSize(width) * height * channels;
  s.width = width;
  s.height = height;
  s.channels = channels;
  s.moments = createBuffer(ctx, 4 * count * sizeof(float));
  s.cross = createBuffer(ctx, count * sizeof(float));
  s.slopes = createBuffer(ctx, 4 * count * sizeof(float));
  s.terms = createBuffer(ctx, 2 * count * sizeof(float));
  s.partials = createBuffer(ctx, groupsFor(uint32_t(count), kSumChunk) * 2 * sizeof(float));
}

void cmdImageLoss(VkCommandBuffer cb, const LossPipelines& p, const ImageLossScratch& s, const Buffer& rendered, const Buffer& target,
                  const Buffer& grad, const Buffer& result, GpuTimer* timer) {
  auto stamp = [&](const char* stage) {
    if (timer) cmdTimerStamp(cb, *timer, stage);
  };
  ImagePush push{s.width, s.height, s.channels, s.width * s.height * s.channels, {}};
  if (!s.moments) fail("image loss: the scratch was not prepared (prepareImageLossScratch)");
  const VkDeviceSize bytes = VkDeviceSize(push.count) * sizeof(float);
  if (rendered.size < bytes || target.size < bytes || grad.size < bytes || result.size < 16)
    fail("image loss: a buffer is smaller than the " + std::to_string(s.width) + "x" + std::to_string(s.height) + "x" +
         std::to_string(s.channels) + " image (or the 16-byte result)");
  for (int k = -f32::kSsimRadius; k <= f32::kSsimRadius; k++) push.window[k + f32::kSsimRadius] = f32::ssimWindowWeight(k);
  // shaders/include/image_loss_pass.glsl: horizontal passes run (pixel block, row, channel),
  // vertical passes (element of a row, row block), each invocation kBlockOutputs outputs.
  const uint32_t hx = groupsFor(groupsFor(s.width, kBlockOutputs), 64), hy = s.height, hz = s.channels;
  const uint32_t vx = groupsFor(s.width * s.channels, 64), vy = groupsFor(s.height, kBlockOutputs);
  cmdBarrier(cb);
  cmdDispatch(cb, p.moments, {bind(rendered), bind(target), bind(s.moments), bind(s.cross)}, &push, hx, hy, hz);
  stamp("moments (horizontal)");
  cmdBarrier(cb);
  cmdDispatch(cb, p.ssim, {bind(rendered), bind(target), bind(s.moments), bind(s.cross), bind(s.slopes), bind(s.terms)}, &push, vx, vy);
  stamp("ssim map (vertical)");
  cmdBarrier(cb);
  // the SSIM map's and |x - y|'s partial sums, and the backward's horizontal pass: both read
  // only what the SSIM pass wrote
  uint32_t partials = groupsFor(push.count, kSumChunk);
  cmdDispatch(cb, p.sum, {bind(s.terms), bind(s.partials)}, &push.count, groupsFor(partials, 64));
  cmdDispatch(cb, p.slopes, {bind(s.slopes), bind(s.moments)}, &push, hx, hy, hz);
  stamp("partial sums + slopes (horizontal)");
  cmdBarrier(cb);
  // L = 0.8 * sum|x-y| / N + 0.2 * (1 - sum S / N)
  float n = float(push.count);
  ReducePush reduce{partials, f32::kLossL1Weight / n, -f32::kLossSsimWeight / n, f32::kLossSsimWeight};
  cmdDispatch(cb, p.reduce, {bind(s.partials), bind(result)}, &reduce, 1);
  cmdDispatch(cb, p.grad, {bind(rendered), bind(target), bind(s.moments), bind(grad)}, &push, vx, vy);
  stamp("total + gradient (vertical)");
}

uint32_t densityPartialCount(uint32_t count) { return groupsFor(count, kGroup); }

void cmdDensityRegularizer(VkCommandBuffer cb, const LossPipelines& p, const Buffer& logits, uint32_t count, const Buffer& gradLogits,
                           const Buffer& partials, const Buffer& result, float weight, uint32_t stride, uint32_t offset) {
  if (count == 0) return;
  const VkDeviceSize bytes = (VkDeviceSize(count - 1) * stride + offset + 1) * 4;
  if (stride == 0 || logits.size < bytes || gradLogits.size < bytes ||
      partials.size < VkDeviceSize(densityPartialCount(count)) * 8 || result.size < 16)
    fail("density regulariser: a buffer is smaller than " + std::to_string(count) + " logits need");
  DensityPush push{count, weight / float(count), stride, offset};
  cmdBarrier(cb);
  cmdDispatch(cb, p.density, {bind(logits), bind(gradLogits), bind(partials)}, &push, densityPartialCount(count));
  cmdBarrier(cb);
  ReducePush reduce{densityPartialCount(count), weight / float(count), 0.0f, 0.0f};
  cmdDispatch(cb, p.reduce, {bind(partials), bind(result)}, &reduce, 1);
}

}  // namespace refrax
