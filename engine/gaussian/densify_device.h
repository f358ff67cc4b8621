#pragma once
// Densification (3DGS strategy) on the device (issue 48): densify.h's rule and output order
// over the device's copies, so a GPU's training step never reads the Gaussians back to clone,
// split or prune them. Three passes (shaders/gaussian/densify_fate, _accept, _scatter): each
// row's fate; the candidates sorted by decreasing statistic (engine/trace/device_order.h's
// stable radix sort: ties by lower row, as the host) and taken within the cap; the kept rows,
// clones and split children written where one exclusive scan of their marks puts them, split
// children drawn with densify_split.glsl's counter-based normals (the host's draws). The host
// reads back seven counts, between the decisions and the new table it allocates.
#include <cstdint>
#include <random>

#include "engine/gaussian/densify.h"
#include "engine/gaussian/gaussian_device_step.h"
#include "engine/gaussian/gaussians.h"
#include "engine/trace/device_order.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct DeviceDensifyPipelines {
  ComputePipeline fate, accept, scatter;
  DeviceOrderPipelines order;  // the scan and the radix sort
};
DeviceDensifyPipelines createDeviceDensifyPipelines(Context& ctx);

// densify(set, stats, config, step, rng, rowMap) on the device: `gaussians` and the optimiser
// `o` (its moments and statistic sums, engine/gaussian/gaussian_device_step.h) replaced by the
// new rows, new rows at zero moments and sums, and the sums kept by a prune alone (the trainer's
// rule). `rng` gives the split draws' key as the host's densify takes it. The counts as
// densify's (milliseconds: the whole call, its two submissions).
DensifyStats densifyOnDevice(Context& ctx, const DeviceDensifyPipelines& p, DeviceGaussians& gaussians, GaussianDeviceOptimiser& o,
                             const DensifyConfig& config, uint32_t step, std::mt19937& rng);

}  // namespace refrax
