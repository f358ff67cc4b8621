#include "engine/gaussian/densify_device.h"

#include <chrono>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"

namespace refrax {
namespace {

struct FatePush {  // densify_fate.comp
  uint32_t n, pruneDue, pruneLarge, densifyDue;
  float minLogit, largeLimit, gradThreshold;
};
struct AcceptPush {  // densify_accept.comp
  uint32_t n, maxGaussians;
  float cloneLimit;
};
struct ScatterPush {  // densify_scatter.comp
  uint32_t n, keepStats, key;
  float logDivisor;
};

// densify_fate.comp's counters, then the scan's slots of the clones, the split parents and the end.
enum ReadBack : uint32_t { kPrunedLow, kPrunedLarge, kCandidates, kCappedOut, kClonesStart, kSplitsStart, kEnd, kReadBackWords };

Buffer words(Context& ctx, uint64_t n) { return createBuffer(ctx, VkDeviceSize(std::max<uint64_t>(n, 1)) * sizeof(uint32_t)); }

}  // namespace

DeviceDensifyPipelines createDeviceDensifyPipelines(Context& ctx) {
  DeviceDensifyPipelines p;
  p.fate = createComputePipeline(ctx, "densify_fate", storageBuffers(6), sizeof(FatePush));
  p.accept = createComputePipeline(ctx, "densify_accept", storageBuffers(5), sizeof(AcceptPush));
  p.scatter = createComputePipeline(ctx, "densify_scatter", storageBuffers(9), sizeof(ScatterPush));
  p.order = createDeviceOrderPipelines(ctx);
  return p;
}

DensifyStats densifyOnDevice(Context& ctx, const DeviceDensifyPipelines& p, DeviceGaussians& gaussians, GaussianDeviceOptimiser& o,
                             const DensifyConfig& config, uint32_t step, std::mt19937& rng) {
  auto start = std::chrono::steady_clock::now();
  validateDensifyConfig(config);
  const uint32_t n = gaussians.count;
  if (o.rows != n || o.rowWidth != kGaussianFloats)
    fail("densifyOnDevice: the optimiser holds " + std::to_string(o.rows) + " rows for " + std::to_string(n) + " Gaussians");
  DensifyStats out;
  out.before = out.after = n;
  const bool cloneSplit = densifyDue(config, step), prune = pruneDue(config, step);
  const uint32_t key = cloneSplit ? uint32_t(rng()) : 0u;  // as the host's densify draws it
  if (n == 0 || (!cloneSplit && !prune)) return out;

  // The decisions and the slots, then the counts read back.
  Buffer fate = words(ctx, n), keys = words(ctx, n), rows = words(ctx, n), tmpKeys = words(ctx, n), tmpRows = words(ctx, n);
  Buffer counters = words(ctx, 4), marks = words(ctx, 3ull * n + 1);
  Buffer readBack = createBuffer(ctx, kReadBackWords * sizeof(uint32_t), 0, MemoryUse::Readback);
  RadixSortScratch sort = createRadixSortScratch(ctx, n);
  Buffer scanSums = createScanBlockSums(ctx, 3 * n + 1);
  FatePush fatePush{n,
                    prune ? 1u : 0u,
                    step >= config.pruneLargeFromStep ? 1u : 0u,
                    cloneSplit ? 1u : 0u,
                    config.minDensity > 0 ? float(densityLogit(config.minDensity)) : -1e30f,
                    config.pruneLargeFraction * config.sceneExtent,
                    config.gradThreshold};
  AcceptPush acceptPush{n, config.maxGaussians, config.percentDense * config.sceneExtent};
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    vkCmdFillBuffer(cb, counters.buffer, 0, VK_WHOLE_SIZE, 0);
    cmdBarrier(cb);
    cmdDispatch(cb, p.fate, {bind(gaussians.params), bind(o.statSums), bind(fate), bind(keys), bind(rows), bind(counters)}, &fatePush,
                groupsFor(n, 256));
    cmdBarrier(cb);
    cmdRadixSort(cb, p.order, keys, rows, tmpKeys, tmpRows, 0, n, sort);
    cmdDispatch(cb, p.accept, {bind(gaussians.params), bind(fate), bind(rows), bind(marks), bind(counters)}, &acceptPush, groupsFor(n, 256));
    cmdBarrier(cb);
    cmdExclusiveScan(cb, p.order, marks, 3 * n + 1, scanSums);
    cmdCopyToHost(cb, counters, 0, readBack, 0, 4 * sizeof(uint32_t));
    for (uint32_t k = 1; k <= 3; k++) cmdCopyToHost(cb, marks, VkDeviceSize(k) * n * 4, readBack, (kCappedOut + k) * 4, 4);
  });
  const uint32_t* c = static_cast<const uint32_t*>(readBack.mapped);
  out.prunedLowDensity = c[kPrunedLow];
  out.prunedLarge = c[kPrunedLarge];
  out.cappedOut = c[kCappedOut];
  out.cloned = c[kSplitsStart] - c[kClonesStart];
  out.split = c[kEnd] - c[kSplitsStart];
  out.after = c[kSplitsStart] + 2 * out.split;

  // The new table.
  DeviceGaussians next;
  next.count = out.after;
  next.params = createBuffer(ctx, VkDeviceSize(std::max<uint32_t>(out.after, 1)) * kGaussianFloats * sizeof(float));
  GaussianDeviceOptimiser grown = createGaussianDeviceOptimiser(ctx, out.after, kGaussianFloats);
  ScatterPush scatterPush{n, cloneSplit ? 0u : 1u, key, float(std::log(double(config.splitScaleDivisor)))};
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdDispatch(cb, p.scatter,
                {bind(gaussians.params), bind(o.m), bind(o.v), bind(o.statSums), bind(marks), bind(next.params), bind(grown.m), bind(grown.v),
                 bind(grown.statSums)},
                &scatterPush, groupsFor(n, 64));
    cmdBarrier(cb);
  });
  gaussians = std::move(next);
  o.rows = grown.rows;
  o.m = std::move(grown.m);
  o.v = std::move(grown.v);
  o.statSums = std::move(grown.statSums);
  out.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace refrax
