#pragma once
// The Gaussians' optimiser step on the device (shaders/gaussian/gaussian_step.comp; issue 48):
// Adam on their table, the density schedule and the densification statistic's sums, each step
// in the step's own command buffer, so the parameters and the gradients stay on the device.
// The host's copies (GaussianSet, TableAdam's moments, the statistic sums) are the same values
// taken when the host needs them: densification, a restart, a checkpoint, the run's files
// (engine/train/train_session.h pullGaussians / pushGaussians). The update is the host table's
// (engine/optim/table_adam.h, shaders/include/adam_update.glsl) and the decay the host's
// (densify.h densityDecay, gaussian_math.glsl decayedLogit), in float.
#include <cstdint>
#include <vector>

#include "engine/gaussian/densify.h"
#include "engine/optim/table_adam.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

// The device's copy of the optimiser's per-Gaussian state, for `rows` Gaussians.
struct GaussianDeviceOptimiser {
  ComputePipeline pipeline;
  uint32_t rows = 0, rowWidth = 0;
  Buffer m, v;      // the Adam moments, the table's layout
  Buffer statSums;  // 2 per Gaussian: the densification statistic's sums
  Buffer groups;    // the groups' columns and this step's step sizes (written in the command buffer)
};

GaussianDeviceOptimiser createGaussianDeviceOptimiser(Context& ctx, uint32_t rows, uint32_t rowWidth);
// Host -> device and back: the moments of `adam` and the statistic sums (`rows` of each).
void uploadGaussianOptimiser(Context& ctx, GaussianDeviceOptimiser& o, const TableAdam& adam, const std::vector<float>& statSums);
void downloadGaussianOptimiser(Context& ctx, const GaussianDeviceOptimiser& o, TableAdam& adam, std::vector<float>& statSums);

// What the density schedule does at this step (densify.h densityDecayDue / densityResetDue).
struct GaussianStepEvents {
  bool decay = false, reset = false;
  float statScale = 1;  // densifyStatScale of the step's batch
};

// Records one step: Adam on `params` from `grads` (every group of `adam` steps once: their
// step counts advance here, on the host, as the host table's would), the events, and
// `stepStats` (2 per Gaussian) added to the sums. A reset zeroes the density group's moments
// and its step count, as resetAdamColumns does.
void cmdGaussianStep(VkCommandBuffer cb, GaussianDeviceOptimiser& o, TableAdam& adam, const Buffer& params, const Buffer& grads,
                     const Buffer& stepStats, const GaussianStepEvents& events, const DensifyConfig& densify,
                     const AdamSettings& settings = {});

}  // namespace refrax
