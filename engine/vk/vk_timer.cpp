#include "engine/vk/vk_timer.h"

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax {

GpuTimer::~GpuTimer() {
  if (ctx && ctx->device && pool) vkDestroyQueryPool(ctx->device, pool, nullptr);
}

void createTimer(Context& ctx, GpuTimer& timer, uint32_t capacity) {
  timer.ctx = &ctx;
  timer.capacity = capacity;
  if (!ctx.caps.timestamps) return;
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = capacity;
  REFRAX_VK(vkCreateQueryPool(ctx.device, &qi, nullptr, &timer.pool));
}

void cmdTimerStart(VkCommandBuffer cb, GpuTimer& timer) {
  timer.labels.clear();
  if (!timer.pool) return;
  vkCmdResetQueryPool(cb, timer.pool, 0, timer.capacity);
  vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timer.pool, 0);
}

void cmdTimerStamp(VkCommandBuffer cb, GpuTimer& timer, const std::string& stage) {
  if (!timer.pool) return;
  if (timer.labels.size() + 1 >= timer.capacity) fail("GPU timer out of timestamp slots");
  timer.labels.push_back(stage);
  vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timer.pool, uint32_t(timer.labels.size()));
}

std::vector<std::pair<std::string, double>> readTimer(GpuTimer& timer) {
  std::vector<std::pair<std::string, double>> out;
  if (!timer.pool || timer.labels.empty()) return out;
  uint32_t n = uint32_t(timer.labels.size()) + 1;
  std::vector<uint64_t> ticks(n);
  REFRAX_VK(vkGetQueryPoolResults(timer.ctx->device, timer.pool, 0, n, n * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  double ns = timer.ctx->properties.limits.timestampPeriod;
  for (uint32_t i = 1; i < n; i++) out.push_back({timer.labels[i - 1], double(ticks[i] - ticks[i - 1]) * ns * 1e-6});
  return out;
}

void addStageMs(std::vector<std::pair<std::string, double>>& stages, const std::string& stage, double ms) {
  for (auto& [name, total] : stages)
    if (name == stage) return void(total += ms);
  stages.push_back({stage, ms});
}

}  // namespace refrax
