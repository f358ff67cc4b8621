#include "engine/gaussian/gaussian_device_step.h"

#include <cmath>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussians.h"
#include "engine/vk/vk_commands.h"

namespace refrax {
namespace {

struct GroupRecord {  // gaussian_step.comp's Group
  uint32_t first, width;
  float stepSize, invSqrtBc2;
};

struct StepPush {  // gaussian_step.comp's push constants
  uint32_t rows, rowWidth, groupCount, densityColumn;
  float beta1, beta2, epsilon, statScale;
  uint32_t decay;
  float decayFactor, decayFloorLogit;
  uint32_t reset;
  float resetLogit;
  uint32_t resetGroup;
};

constexpr uint32_t kMaxGroups = 16;

}  // namespace

GaussianDeviceOptimiser createGaussianDeviceOptimiser(Context& ctx, uint32_t rows, uint32_t rowWidth) {
  GaussianDeviceOptimiser o;
  o.pipeline = createComputePipeline(ctx, "gaussian_step", storageBuffers(7), sizeof(StepPush));
  o.rows = rows;
  o.rowWidth = rowWidth;
  const VkDeviceSize table = VkDeviceSize(std::max<uint32_t>(rows, 1)) * rowWidth * sizeof(float);
  o.m = createBuffer(ctx, table);
  o.v = createBuffer(ctx, table);
  o.statSums = createBuffer(ctx, VkDeviceSize(std::max<uint32_t>(rows, 1)) * 2 * sizeof(float));
  o.groups = createBuffer(ctx, kMaxGroups * sizeof(GroupRecord));
  return o;
}

void uploadGaussianOptimiser(Context& ctx, GaussianDeviceOptimiser& o, const TableAdam& adam, const std::vector<float>& statSums) {
  const size_t n = size_t(o.rows) * o.rowWidth;
  if (adam.rowWidth != o.rowWidth || adam.m.size() != n || adam.v.size() != n || statSums.size() != size_t(o.rows) * 2)
    fail("uploadGaussianOptimiser: the host table does not match the device's rows");
  if (n == 0) return;
  upload(ctx, o.m, adam.m.data(), n * sizeof(float));
  upload(ctx, o.v, adam.v.data(), n * sizeof(float));
  upload(ctx, o.statSums, statSums.data(), statSums.size() * sizeof(float));
}

void downloadGaussianOptimiser(Context& ctx, const GaussianDeviceOptimiser& o, TableAdam& adam, std::vector<float>& statSums) {
  const size_t n = size_t(o.rows) * o.rowWidth;
  adam.m = downloadVector<float>(ctx, o.m, n);
  adam.v = downloadVector<float>(ctx, o.v, n);
  statSums = downloadVector<float>(ctx, o.statSums, size_t(o.rows) * 2);
}

void cmdGaussianStep(VkCommandBuffer cb, GaussianDeviceOptimiser& o, TableAdam& adam, const Buffer& params, const Buffer& grads,
                     const Buffer& stepStats, const GaussianStepEvents& events, const DensifyConfig& densify, const AdamSettings& s) {
  if (adam.groups.size() > kMaxGroups) fail("cmdGaussianStep: more Adam groups than the step holds");
  if (adam.rowWidth != o.rowWidth) fail("cmdGaussianStep: the Adam table's rows are not the optimiser's");
  GroupRecord records[kMaxGroups] = {};
  uint32_t densityGroup = 0;
  for (size_t g = 0; g < adam.groups.size(); g++) {
    AdamColumns& group = adam.groups[g];
    group.step++;  // the host table's bookkeeping (tableAdamStep)
    records[g] = {group.first, group.width, float(group.lr.at(group.step) / (1.0 - std::pow(s.beta1, group.step))),
                  float(1.0 / std::sqrt(1.0 - std::pow(s.beta2, group.step)))};
    if (group.first <= f32::kGaussLogitDensity && f32::kGaussLogitDensity < group.first + group.width) densityGroup = uint32_t(g);
  }
  if (o.rows == 0) return;
  vkCmdUpdateBuffer(cb, o.groups.buffer, 0, sizeof(records), records);
  cmdBarrier(cb);
  StepPush push{};
  push.rows = o.rows;
  push.rowWidth = o.rowWidth;
  push.groupCount = uint32_t(adam.groups.size());
  push.densityColumn = f32::kGaussLogitDensity;
  push.beta1 = float(s.beta1);
  push.beta2 = float(s.beta2);
  push.epsilon = float(s.epsilon);
  push.statScale = events.statScale;
  push.decay = events.decay ? 1u : 0u;
  push.decayFactor = densify.decayFactor;
  push.decayFloorLogit = densify.decayFloor > 0 ? float(densityLogit(densify.decayFloor)) : -1e30f;
  push.reset = events.reset ? 1u : 0u;
  push.resetLogit = float(densityLogit(densify.resetDensity));
  push.resetGroup = densityGroup;
  cmdDispatch(cb, o.pipeline, {bind(params), bind(grads), bind(o.m), bind(o.v), bind(o.groups), bind(stepStats), bind(o.statSums)}, &push,
              groupsFor(o.rows, 64));
  if (events.reset) adam.groups[densityGroup].step = 0;  // resetAdamColumns: the group starts afresh
}

}  // namespace refrax
