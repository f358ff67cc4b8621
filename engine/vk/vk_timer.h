#pragma once
// GPU timestamps for stage timing: stamp after each stage, read back milliseconds between
// consecutive stamps. Devices without compute timestamps report nothing (caps.timestamps).
#include <volk.h>

#include <string>
#include <utility>
#include <vector>

namespace refrax {

struct Context;

struct GpuTimer {
  Context* ctx = nullptr;
  VkQueryPool pool = VK_NULL_HANDLE;
  uint32_t capacity = 0;
  std::vector<std::string> labels;  // labels[i] names the stage that ends at stamp i+1

  GpuTimer() = default;
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;
  ~GpuTimer();
};

void createTimer(Context& ctx, GpuTimer& timer, uint32_t capacity = 64);
void cmdTimerStart(VkCommandBuffer cb, GpuTimer& timer);                       // resets, first stamp
void cmdTimerStamp(VkCommandBuffer cb, GpuTimer& timer, const std::string& stage);  // stage ended here
// After the submission has completed: (stage, ms) for every stamped stage.
std::vector<std::pair<std::string, double>> readTimer(GpuTimer& timer);
// Adds `ms` to the stage's total in `stages`, a new stage last (a breakdown summed over frames).
void addStageMs(std::vector<std::pair<std::string, double>>& stages, const std::string& stage, double ms);

}  // namespace refrax
