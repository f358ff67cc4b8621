#pragma once
// --benchmark: per-stage GPU ms and wall time of the frames after a warm-up (lavapipe compiles
// each pipeline on first use), printed with what the trace cost depends on.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/frame/frame_renderer.h"
#include "viewer/panels.h"
#include "engine/frame/view_scene.h"

namespace refrax {

struct Benchmark {
  long warmup = 0, frames = 0;
  double wallMs = 0;
  std::map<std::string, double> stageMs;
  std::vector<std::string> order;
};

// One frame's GPU ms per stage, counted once past the warm-up.
void addStages(Benchmark& b, const std::vector<std::pair<std::string, double>>& stages);
// The summary lines; scene may be null (a built-in surface alone).
void printBenchmark(Context& ctx, const Benchmark& b, ViewScene* scene, const ViewerState& state, const FrameStats& stats,
                    const FrameRenderer& renderer);

}  // namespace refrax
