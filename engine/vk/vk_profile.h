#pragma once
// Per-stage profile of whatever the device runs while a profiler is attached to the context
// (training steps, `refrax train --profile` and metrics.json): GPU milliseconds per named
// stage, from timestamps written at the end of each stage, and host milliseconds per named
// host stage. Every submitAndWait of a profiled context starts the timer and reads it back
// after the wait, so stages are stamped with profileStage(cb, ctx, "name") after they are
// recorded: the time since the previous stamp of the same submission is the stage's.
// On devices without compute timestamps only the host stages and the wall time are known.
#include <volk.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/vk/vk_timer.h"

namespace refrax {

struct Context;

struct StageTotals {
  double ms = 0;
  uint64_t calls = 0;
};

struct GpuProfiler {
  GpuTimer timer;
  GpuTimer* recording = nullptr;              // the timer of the submission being recorded (timer, or a slot's)
  bool gpu = false;                           // the device writes timestamps
  std::map<std::string, StageTotals> device;  // GPU ms by stage
  std::map<std::string, StageTotals> host;    // host ms by stage (work between submits)
  uint64_t submits = 0;
  uint64_t dispatches = 0;  // compute dispatches recorded (each costs lavapipe tens of microseconds)
  double deviceMs = 0;  // sum over `device`
  double wallMs = 0;  // wall time of the profiled steps (profileStepEnd)
  int steps = 0;
  std::vector<float> stepMs;  // each step's wall time: the median leaves out one-off costs (pipelines built on first use)
};

// Attaches a profiler to the context (every later submitAndWait is timed) / detaches it.
void attachProfiler(Context& ctx, GpuProfiler& profiler);
void detachProfiler(Context& ctx);

// The GPU stage that ended here (no-op without an attached profiler).
void profileStage(VkCommandBuffer cb, Context& ctx, const std::string& stage);

// Host time of a stage, measured from construction to destruction, less the GPU time of the
// submissions made meanwhile (those are counted as GPU stages); no-op without a profiler.
struct HostStage {
  HostStage(Context& ctx, std::string stage);
  ~HostStage();
  HostStage(const HostStage&) = delete;
  HostStage& operator=(const HostStage&) = delete;
  Context& ctx;
  std::string stage;
  std::chrono::steady_clock::time_point start;
  double deviceMsAtStart = 0;
};

// Called by submitAndWait around a submission.
void profileSubmitBegin(VkCommandBuffer cb, Context& ctx);
void profileSubmitEnd(Context& ctx);
// The same for a submission not waited for (submitWithoutWait): its stamps go to `timer`
// (one per slot in flight), whose stages profileSubmitDone adds once its fence has signalled.
void profileSubmitBegin(VkCommandBuffer cb, Context& ctx, GpuTimer& timer);
void profileSubmitDone(GpuProfiler& profiler, GpuTimer& timer);

// One profiled step ended after `wallMs`.
void profileStepEnd(GpuProfiler& profiler, double wallMs);

// Mean milliseconds per step of each stage (GPU, host) and of the rest.
struct ProfileRow {
  std::string stage;
  bool gpu = true;
  double msPerStep = 0;
};
std::vector<ProfileRow> profileRows(const GpuProfiler& profiler);  // largest first
// "stage 12.3 ms, stage 4.5 ms, stage 1.0 ms": the top `n` rows.
std::string profileTop(const GpuProfiler& profiler, size_t n);
// A table for the terminal: one row per stage, ms per step and share of the step.
std::string profileTable(const GpuProfiler& profiler);
// {"steps", "timestamps", "wall_ms_per_step", "median_step_ms", "slowest_step_ms", "gpu_ms_per_step",
//  "host_ms_per_step", "submits_per_step", "dispatches_per_step", "gpu": {stage: ms per step},
//  "host": {stage: ms per step}}
double medianStepMs(const GpuProfiler& profiler);
nlohmann::json profileJson(const GpuProfiler& profiler);

}  // namespace refrax
