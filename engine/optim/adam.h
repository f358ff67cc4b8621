#pragma once
// Adam on the device, one state per parameter group (as torch.optim.Adam with one param
// group per tensor, which is what 3D Gaussian Splatting trains with):
//   m = b1 m + (1 - b1) g;  v = b2 v + (1 - b2) g^2;
//   p -= lr / (1 - b1^t) * m / (sqrt(v) / sqrt(1 - b2^t) + eps)      (t = steps taken, from 1)
// b1 0.9, b2 0.999, eps 1e-15. A group's parameters and gradients live in caller-owned float
// buffers (at a float offset, so several groups may share one buffer); the group owns m and v.
// The height MLP's weights are such a group; the Gaussians' table, which densification
// rebuilds, is on the host (engine/optim/table_adam.h), with the same update.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

// 3DGS's log-linear decay: lr(t) = lr0^(1-s) * lr1^s, s = clamp(t / steps, 0, 1).
// A constant rate has initial == final.
struct LearningRateSchedule {
  double initial = 0;
  double final = 0;
  int steps = 1;
  double at(int step) const;
};

struct AdamSettings {
  double beta1 = 0.9;
  double beta2 = 0.999;
  double epsilon = 1e-15;
  // > 0: each step scaled by (|m^| / sqrt(v^))^agreementPower, the agreement of the gradients
  // averaged (shaders/include/adam_update.glsl adamUpdateAgreed); the device step only.
  double agreementPower = 0;
};

struct AdamGroup {
  std::string name;
  LearningRateSchedule lr;
  uint32_t rowWidth = 1;  // floats per row
  uint32_t rows = 0;
  int step = 0;           // updates taken (the t of the bias correction)
  Buffer m, v;            // rows * rowWidth floats each
  uint32_t count() const { return rows * rowWidth; }
};

// The reference learning rates (docs/method.md §1.6): positions 1.6e-4 * extent -> 1.6e-6 * extent and
// the height MLP 5e-4 -> 5e-6 over 30k steps; density 0.05, SH DC 2.5e-3, SH rest 1.25e-4,
// rotation 1e-3, scale 5e-3 constant. Names: position density sh_dc sh_rest rotation scale height_mlp.
struct AdamGroupRate {
  std::string name;
  LearningRateSchedule lr;
};
std::vector<AdamGroupRate> referenceLearningRates(double sceneExtent);
// The entry called `name` of referenceLearningRates (throws refrax::Error for an unknown name).
LearningRateSchedule referenceLearningRate(const std::string& name, double sceneExtent);

struct AdamPipelines {
  ComputePipeline step;      // whole workgroups
  ComputePipeline stepTail;  // the last partial workgroup
};
AdamPipelines createAdamPipelines(Context& ctx);

// A group of `rows` rows of `rowWidth` floats with zero moments.
AdamGroup createAdamGroup(Context& ctx, const std::string& name, const LearningRateSchedule& lr, uint32_t rowWidth, uint32_t rows);

// Records one update of the group (advances group.step, uses lr.at(group.step) after the
// advance, as 3DGS's update_learning_rate(iteration) with iterations from 1). params and
// grads hold the group's floats from `offset`. With clearGradients the gradients are set to 0
// after use, ready for the next backward to accumulate into.
void cmdAdamStep(VkCommandBuffer cb, const AdamPipelines& p, AdamGroup& group, const Buffer& params, const Buffer& grads,
                 uint32_t offset = 0, bool clearGradients = false, const AdamSettings& settings = {});

// Row i of a rebuilt table comes from old row sourceRow[i], or is new (kNewRow): zero
// (engine/optim/table_adam.h remapTableAdamRows, engine/gaussian/densify.h).
constexpr uint32_t kNewRow = 0xFFFFFFFFu;

}  // namespace refrax
