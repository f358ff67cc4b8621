#include "engine/train/step_probe.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "engine/train/train_session.h"

namespace refrax {

StepProbe probeStepsForTime(Context& ctx, const TrainConfig& resolved, const Dataset& dataset, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  TrainConfig c = resolved;
  c.schedule.surfaceFreeze = 0;   // every probed step learns the water, as most of the run does
  c.schedule.surfaceUntil = 0;
  c.schedule.gaussianRestarts.clear();
  c.surfaceGate = 0;              // (it needs restarts)
  c.waterSignCheck = false;
  c.waterScaleSearch = false;
  c.sweepLoss = 0;                // a study's host work, not the step's
  c.initDepth = InitDepth::Box;   // the sweep's time is not the step's
  auto probe = createTrainSession(ctx, c, dataset);
  for (int k = 0; k < kProbeWarmUp; k++) trainStep(*probe);
  const auto timed = std::chrono::steady_clock::now();
  for (int k = 0; k < kProbeTimed; k++) trainStep(*probe);
  const auto end = std::chrono::steady_clock::now();
  StepProbe p;
  p.msPerStep = std::chrono::duration<double, std::milli>(end - timed).count() / kProbeTimed;
  p.probeSeconds = std::chrono::duration<double>(end - start).count();
  p.steps = std::max(kMinProbedSteps, int(std::floor(0.8 * seconds * 1000.0 / std::max(p.msPerStep, 1e-3))));
  p.steps = std::min(p.steps, 10000000);
  return p;
}

std::string stepProbeLine(double seconds, const StepProbe& p) {
  char text[200];
  std::snprintf(text, sizeof text, "--time-limit %g: %d probe steps took %.1f ms each (%.0f s in all): %d steps", seconds, kProbeTimed,
                p.msPerStep, p.probeSeconds, p.steps);
  return text;
}

}  // namespace refrax
