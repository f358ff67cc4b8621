// refrax bench proxy-order: the Gaussian proxies' median-split order at --gaussians Gaussians,
// as training refreshes it every 100 steps, two ways side by side in one run: on the host as
// before issue 48 (the parameters read back, the means ordered by presort.h medianSplitOrder,
// the order uploaded) and on the device (engine/trace/device_order.h, one submission, nothing
// read back). Median wall times; the two orders must agree.
#include <cstdio>
#include <random>
#include <vector>

#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/gaussian/gaussians.h"
#include "engine/trace/device_order.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

int runProxyOrderBench(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const uint32_t n = uint32_t(args.getInt("gaussians", 100000));
  const int runs = int(args.getInt("runs", 7));
  std::mt19937 rng(1);
  DeviceGaussians dev = uploadGaussians(*ctx, randomGaussians(rng, n));
  Buffer hostBuilt = createBuffer(*ctx, VkDeviceSize(n) * 4), deviceBuilt = createBuffer(*ctx, VkDeviceSize(n) * 4);

  double hostMs = bench::medianMs(1, runs, [&] {
    std::vector<uint32_t> order = gaussianMeansOrder(downloadGaussians(*ctx, dev));
    upload(*ctx, hostBuilt, order.data(), order.size() * 4);
  });
  DeviceOrderPipelines pipelines = createDeviceOrderPipelines(*ctx);
  MedianSplitScratch scratch = createMedianSplitScratch(*ctx, n);
  const PointLayout means{kGaussianFloats, f32::kGaussMean};
  double deviceMs = bench::medianMs(1, runs, [&] {
    submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdMedianSplitOrder(cb, pipelines, scratch, dev.params, means, n, deviceBuilt); });
  });
  const bool same = downloadVector<uint32_t>(*ctx, hostBuilt, n) == downloadVector<uint32_t>(*ctx, deviceBuilt, n);

  std::printf("device: %s\n", ctx->caps.name.c_str());
  std::printf("proxy order of %u Gaussians (%u split levels), median of %d:\n", n, medianSplitLevels(n), runs);
  std::printf("  host (read back, order, upload)   %8.2f ms\n", hostMs);
  std::printf("  device (one submission)           %8.2f ms  (%.2fx the host's)\n", deviceMs, deviceMs / hostMs);
  std::printf("  orders %s\n", same ? "agree" : "DIFFER");
  return same ? 0 : 1;
}

REFRAX_BENCH_SUITE({"proxy-order", "the proxies' median-split order at --gaussians, on the host against on the device",
                    {{"gaussians", "N", "Gaussian count", "100000"}, {"runs", "N", "timed runs (median)", "7"}},
                    runProxyOrderBench});

}  // namespace
}  // namespace refrax
