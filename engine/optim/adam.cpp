#include "engine/optim/adam.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {
namespace {

struct StepPush {
  uint32_t count, offset, clearGradients;
  float beta1, beta2, epsilon, stepSize, invSqrtBc2;
  uint32_t first;
  float invBc1, agreementPower;
};
constexpr uint32_t kStepGroup = 256;  // adam_step's local size

}  // namespace

double LearningRateSchedule::at(int step) const {
  if (initial == final) return initial;
  double s = std::clamp(double(step) / double(std::max(steps, 1)), 0.0, 1.0);
  return std::exp((1.0 - s) * std::log(initial) + s * std::log(final));
}

std::vector<AdamGroupRate> referenceLearningRates(double extent) {
  auto constant = [](double lr) { return LearningRateSchedule{lr, lr, 1}; };
  return {
      {"position", {1.6e-4 * extent, 1.6e-6 * extent, 30000}},
      {"density", constant(0.05)},
      {"sh_dc", constant(2.5e-3)},
      {"sh_rest", constant(1.25e-4)},
      {"rotation", constant(1e-3)},
      {"scale", constant(5e-3)},
      {"height_mlp", {5e-4, 5e-6, 30000}},
  };
}

LearningRateSchedule referenceLearningRate(const std::string& name, double extent) {
  for (const auto& g : referenceLearningRates(extent))
    if (g.name == name) return g.lr;
  fail("no reference learning rate for a parameter group called '" + name + "'");
}

AdamPipelines createAdamPipelines(Context& ctx) {
  AdamPipelines p;
  const std::vector<VkDescriptorType> buffers = {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer};
  p.step = createComputePipeline(ctx, "adam_step", buffers, sizeof(StepPush), {{0, 0u}});  // whole workgroups
  p.stepTail = createComputePipeline(ctx, "adam_step", buffers, sizeof(StepPush), {{0, 1u}});  // guarded stores
  return p;
}

AdamGroup createAdamGroup(Context& ctx, const std::string& name, const LearningRateSchedule& lr, uint32_t rowWidth, uint32_t rows) {
  if (rowWidth == 0) fail("Adam group '" + name + "': a row must hold at least one float");
  AdamGroup g;
  g.name = name;
  g.lr = lr;
  g.rowWidth = rowWidth;
  g.rows = rows;
  VkDeviceSize bytes = std::max<VkDeviceSize>(VkDeviceSize(rows) * rowWidth * sizeof(float), 4);
  g.m = createBuffer(ctx, bytes);
  g.v = createBuffer(ctx, bytes);
  fillBuffer(ctx, g.m, 0);
  fillBuffer(ctx, g.v, 0);
  return g;
}

void cmdAdamStep(VkCommandBuffer cb, const AdamPipelines& p, AdamGroup& g, const Buffer& params, const Buffer& grads, uint32_t offset,
                 bool clearGradients, const AdamSettings& s) {
  if (g.count() == 0) {
    g.step++;
    return;
  }
  const VkDeviceSize end = (VkDeviceSize(offset) + g.count()) * sizeof(float);
  if (params.size < end || grads.size < end || g.m.size < VkDeviceSize(g.count()) * 4 || g.v.size < VkDeviceSize(g.count()) * 4)
    fail("Adam group '" + g.name + "': the parameter or gradient buffer is smaller than " + std::to_string(g.count()) + " floats from offset " +
         std::to_string(offset));
  g.step++;
  double lr = g.lr.at(g.step);
  double bc1 = 1.0 - std::pow(s.beta1, g.step), bc2 = 1.0 - std::pow(s.beta2, g.step);
  StepPush push{g.count(),       offset, clearGradients ? 1u : 0u, float(s.beta1), float(s.beta2), float(s.epsilon),
                float(lr / bc1), float(1.0 / std::sqrt(bc2)), 0,  float(1.0 / bc1), float(s.agreementPower)};
  const uint32_t whole = g.count() / kStepGroup;
  cmdBarrier(cb);
  if (whole) cmdDispatch(cb, p.step, {bind(params), bind(grads), bind(g.m), bind(g.v)}, &push, whole);
  if (g.count() % kStepGroup) {
    push.first = whole * kStepGroup;
    cmdDispatch(cb, p.stepTail, {bind(params), bind(grads), bind(g.m), bind(g.v)}, &push, 1);
  }
}

}  // namespace refrax
