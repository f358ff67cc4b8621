#pragma once
// --time-limit without --steps (issue 45): the steps that fit the time on this device, so the
// schedule (the surface's freeze, the restarts, the learning rates' decay) spans the run the
// time allows rather than being cut off by it. A probe session of the run's configuration
// trains a few steps with the surface learning from the first (the costlier step), timed.
#include <string>

#include "engine/dataset/dataset.h"
#include "engine/run/train_config.h"

namespace refrax {

struct Context;

struct StepProbe {
  int steps = 0;             // what fits
  double msPerStep = 0;      // the probe's mean step
  double probeSeconds = 0;   // the probe's own time (session, warm-up and timed steps)
};

// `resolved`: the run's configuration (resolveSceneConfig done). The step time is the mean of
// kTimed steps after kWarmUp; the steps are what fills `seconds` at that time, less a fifth for
// what the probe does not see (the restarts' plane sweeps, densification, checkpoints), at
// least kMinSteps. The probe session is discarded.
StepProbe probeStepsForTime(Context& ctx, const TrainConfig& resolved, const Dataset& dataset, double seconds);
constexpr int kProbeWarmUp = 10, kProbeTimed = 30, kMinProbedSteps = 100;

// "--time-limit 600: 20 probe steps took 34.2 ms each (6 s in all): 15,780 steps".
std::string stepProbeLine(double seconds, const StepProbe& probe);

}  // namespace refrax
