// refrax bench densify: one densification step as the trainer runs it, at --gaussians
// Gaussians: download the parameters and statistics, densify on the host (about 10% cloned
// or split, a few % pruned), upload the new set, remap the Adam moments of the six 3DGS
// parameter groups; the same step on the device (densify_device.h, as a GPU trains); plus
// density decay and reset on the host. Median wall times.
#include <cstdio>
#include <random>
#include <vector>

#include "engine/gaussian/gaussian_adam.h"
#include "engine/gaussian/densify.h"
#include "engine/gaussian/densify_device.h"
#include "engine/gaussian/gaussians.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_context.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

int runDensifyBench(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const uint32_t n = uint32_t(args.getInt("gaussians", 100000));
  const int runs = int(args.getInt("runs", 7));

  std::mt19937 rng(1);
  RandomGaussianOptions options;
  options.sigmaMin = 0.002f;  // about half clone-sized, half split-sized at extent 1
  options.sigmaMax = 0.03f;
  options.densityMin = 0.001f;
  GaussianSet set = randomGaussians(rng, n, options);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<float> stats(2 * size_t(n));
  for (uint32_t i = 0; i < n; i++) {
    stats[2 * i + 1] = float(1 + int(20 * U(rng)));
    stats[2 * i] = stats[2 * i + 1] * (U(rng) < 0.1f ? 5e-4f : 1e-4f);  // 10% above the threshold
  }
  DeviceGaussians dev = uploadGaussians(*ctx, set);
  Buffer statsBuffer = createBufferFrom(*ctx, stats);
  DensifyConfig config;

  double downloadMs = bench::medianMs(1, runs, [&] {
    GaussianSet host = downloadGaussians(*ctx, dev);
    std::vector<float> s = downloadVector<float>(*ctx, statsBuffer, stats.size());
  });
  DensifyStats last;
  std::vector<uint32_t> rowMap;
  GaussianSet result;
  double densifyMs = bench::medianMs(1, runs, [&] {
    result = set;
    std::mt19937 r(5);
    last = densify(result, stats, config, 600, r, rowMap);
  });
  double copyMs = bench::medianMs(1, runs, [&] { GaussianSet copy = set; });  // the copy inside the timed densify loop
  double uploadMs = bench::medianMs(1, runs, [&] { DeviceGaussians d = uploadGaussians(*ctx, result); });

  // The Gaussians' Adam table (six column groups), remapped as the trainer does after densify.
  const TableAdam fresh = createGaussianAdam(1.0, 1, n);
  double remapMs = bench::medianMs(1, runs, [&] {
    TableAdam adam = fresh;
    remapTableAdamRows(adam, rowMap);
  });
  double createMs = bench::medianMs(1, runs, [&] { TableAdam adam = fresh; });  // the copy inside the timed remap
  // The same step on the device (densify_device.h), as a GPU's training runs it: the table,
  // its moments and sums stay there; two submissions and seven counts read back.
  DeviceDensifyPipelines pipelines = createDeviceDensifyPipelines(*ctx);
  DensifyStats onDevice;
  double deviceMs = bench::medianMs(1, runs, [&] {
    DeviceGaussians d = uploadGaussians(*ctx, set);
    GaussianDeviceOptimiser o = createGaussianDeviceOptimiser(*ctx, n, kGaussianFloats);
    upload(*ctx, o.statSums, stats.data(), stats.size() * sizeof(float));
    std::mt19937 r(5);
    onDevice = densifyOnDevice(*ctx, pipelines, d, o, config, 600, r);
  });
  double deviceSetupMs = bench::medianMs(1, runs, [&] {  // the uploads inside the timed device step
    DeviceGaussians d = uploadGaussians(*ctx, set);
    GaussianDeviceOptimiser o = createGaussianDeviceOptimiser(*ctx, n, kGaussianFloats);
    upload(*ctx, o.statSums, stats.data(), stats.size() * sizeof(float));
  });
  double decayMs = bench::medianMs(1, runs, [&] { densityDecay(result, config); });
  double resetMs = bench::medianMs(1, runs, [&] { densityReset(result, config); });

  std::printf("device: %s\n", ctx->caps.name.c_str());
  std::printf("densify %u -> %u Gaussians (%u cloned, %u split, %u pruned)\n", last.before, last.after, last.cloned, last.split,
              last.prunedLowDensity + last.prunedLarge);
  std::printf("  download params + stats   %8.2f ms\n", downloadMs);
  std::printf("  densify (host)            %8.2f ms\n", densifyMs - copyMs);
  std::printf("  upload new set            %8.2f ms\n", uploadMs);
  std::printf("  remap the Adam table      %8.2f ms\n", remapMs - createMs);
  const double hostStepMs = downloadMs + densifyMs - copyMs + uploadMs + remapMs - createMs;
  std::printf("  the host's step, together %8.2f ms\n", hostStepMs);
  std::printf("  densify on the device     %8.2f ms  (%.2fx the host's step; %u -> %u, the host's counts: %s)\n", deviceMs - deviceSetupMs,
              (deviceMs - deviceSetupMs) / hostStepMs, onDevice.before, onDevice.after,
              onDevice.after == last.after && onDevice.cloned == last.cloned && onDevice.split == last.split ? "yes" : "NO");
  std::printf("  density decay (host)      %8.2f ms\n", decayMs);
  std::printf("  density reset (host)      %8.2f ms\n", resetMs);
  return 0;
}

REFRAX_BENCH_SUITE({"densify", "one densification step at --gaussians (download, host densify, upload, Adam remap)",
                    {{"gaussians", "N", "Gaussian count", "100000"}, {"runs", "N", "timed runs (median)", "7"}},
                    runDensifyBench});

}  // namespace
}  // namespace refrax
