// refrax bench losses: the per-step pieces around the tracer at a training image size — the
// image loss with its gradient (four window passes and a reduction), the density regulariser,
// Adam over a Gaussian set, and the camera rays — median wall time per submission, plus the
// loss's per-pass GPU timestamps where the device has them.
#include <cstdio>
#include <random>
#include <vector>

#include "engine/optim/adam.h"
#include "engine/camera/camera_rays.h"
#include "engine/loss/image_loss.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

int runLossBench(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const uint32_t size = uint32_t(args.getInt("size", 392));
  const uint32_t gaussians = uint32_t(args.getInt("gaussians", 100000));
  const int runs = int(args.getInt("runs", 10));
  const uint32_t channels = 3, count = size * size * channels;

  std::mt19937 rng(1);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<float> x(count), y(count);
  for (uint32_t i = 0; i < count; i++) {
    y[i] = U(rng);
    x[i] = std::min(1.0f, std::max(0.0f, y[i] + 0.2f * (U(rng) - 0.5f)));
  }
  LossPipelines loss = createLossPipelines(*ctx);
  ImageLossScratch scratch;
  prepareImageLossScratch(*ctx, scratch, size, size, channels);
  Buffer xb = createBufferFrom(*ctx, x), yb = createBufferFrom(*ctx, y);
  Buffer gb = createBuffer(*ctx, count * 4), rb = createBuffer(*ctx, 16);
  double lossMs = bench::medianMs(2, runs, [&] {
    submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdImageLoss(cb, loss, scratch, xb, yb, gb, rb); });
  });
  std::printf("image loss + gradient, %ux%ux%u: %.2f ms (median of %d)\n", size, size, channels, lossMs, runs);
  if (ctx->caps.timestamps) {
    // the same passes, stamped one by one
    GpuTimer timer;
    createTimer(*ctx, timer);
    submitAndWait(*ctx, [&](VkCommandBuffer cb) {
      cmdTimerStart(cb, timer);
      cmdImageLoss(cb, loss, scratch, xb, yb, gb, rb, &timer);
    });
    for (auto& [stage, ms] : readTimer(timer)) std::printf("  gpu timestamp %s: %.2f ms\n", stage.c_str(), ms);
  }

  std::vector<float> logits(gaussians);
  for (auto& l : logits) l = 4.0f * (U(rng) - 0.5f);
  Buffer lb = createBufferFrom(*ctx, logits), glb = createBuffer(*ctx, gaussians * 4);
  Buffer pb = createBuffer(*ctx, densityPartialCount(gaussians) * 8);
  fillBuffer(*ctx, glb, 0);
  double regMs = bench::medianMs(2, runs, [&] {
    submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdDensityRegularizer(cb, loss, lb, gaussians, glb, pb, rb); });
  });
  std::printf("density regulariser, %u Gaussians: %.2f ms\n", gaussians, regMs);

  // Adam over every Gaussian group: 3 + 1 + 3 + 45 + 4 + 3 floats per Gaussian
  AdamPipelines adam = createAdamPipelines(*ctx);
  const uint32_t widths[6] = {3, 1, 3, 45, 4, 3};
  const char* names[6] = {"position", "density", "sh_dc", "sh_rest", "rotation", "scale"};
  std::vector<AdamGroup> groups;
  std::vector<Buffer> params, grads;
  for (int g = 0; g < 6; g++) {
    groups.push_back(createAdamGroup(*ctx, names[g], referenceLearningRate(names[g], 1.0), widths[g], gaussians));
    params.push_back(createBuffer(*ctx, VkDeviceSize(gaussians) * widths[g] * 4));
    grads.push_back(createBuffer(*ctx, VkDeviceSize(gaussians) * widths[g] * 4));
    fillBuffer(*ctx, params.back(), 0);
    fillBuffer(*ctx, grads.back(), 0x3A83126Fu);  // 0.001
  }
  double adamMs = bench::medianMs(2, runs, [&] {
    submitAndWait(*ctx, [&](VkCommandBuffer cb) {
      for (int g = 0; g < 6; g++) cmdAdamStep(cb, adam, groups[g], params[g], grads[g]);
    });
  });
  std::printf("Adam, 6 groups, %u Gaussians (59 floats each): %.2f ms\n", gaussians, adamMs);

  CameraRayPipelines rays = createCameraRayPipelines(*ctx);
  Camera cam;
  cam.width = cam.height = int(size);
  cam.fx = cam.fy = size;
  cam.cx = cam.cy = size / 2.0;
  Buffer rayBuf = createBuffer(*ctx, VkDeviceSize(size) * size * sizeof(GpuRay));
  double rayMs = bench::medianMs(2, runs, [&] {
    submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, rays, cam, rayBuf, 0.0f, 100.0f); });
  });
  std::printf("camera rays, %ux%u: %.2f ms\n", size, size, rayMs);
  std::printf("device: %s (%s)\n", ctx->caps.name.c_str(), ctx->caps.driver.c_str());
  return 0;
}

REFRAX_BENCH_SUITE({"losses",
                    "image loss + gradient, density regulariser, Adam, camera rays at a training size",
                    {{"size", "N", "image side in pixels", "392"},
                     {"gaussians", "N", "Gaussians for the regulariser and Adam", "100000"},
                     {"runs", "N", "timed runs (median reported)", "10"}},
                    runLossBench});

}  // namespace
}  // namespace refrax
