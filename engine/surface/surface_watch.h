#pragma once
// Watching the learned water for roughening (issue 29): with no ground truth a run cannot
// measure its surface's error, but it can see the surface's shape and its own loss. A surface
// that keeps growing rougher while the image loss no longer falls is buying nothing for its
// relief. The run samples the surface's shape over the seen water with its mean training loss
// and judges the series at the end. On short runs the loss keeps falling as the Gaussians fit,
// and the rule has not fired on a real run yet
// (docs/experiments/2026-11-27-surface-checks.md; the plane-sweep agreement,
// engine/train/plane_sweep.h, is the check that has caught wrong surfaces there).
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/surface/surface_prior.h"  // GridLayout

namespace refrax {

// The seen water's shape: over the grid vertices of weight > 0 (the trainer weighs a vertex
// by the training views that see it), the weighted RMS slope of the grid's edges (both ends
// seen, weighted by their mean weight) and the weighted RMS height about the weighted mean.
struct SurfaceShape {
  double slopeRms = 0;   // dimensionless (m / m)
  double heightRms = 0;  // m
};
SurfaceShape measureSurfaceShape(const std::vector<float>& heights, const GridLayout& grid, const std::vector<double>& weights);

// One point of the series: after `step`, the mean image loss of the steps since the last sample
// and the surface's shape as it stood then.
struct SurfaceWatchSample {
  int step = 0;
  double loss = 0;
  SurfaceShape shape;
};

// The verdict over a run's samples from `learnFrom` (the first step the surface learns) on.
// The last `window` fraction of the surface's learning is compared with the samples just before
// it: the surface roughened when its RMS slope grew by more than `slopeGrowth` (a fraction)
// while the mean loss fell by less than `lossFall` (a fraction).
struct RougheningRule {
  double window = 1.0 / 3.0;
  double slopeGrowth = 0.25;
  double lossFall = 0.02;
};
struct RougheningVerdict {
  bool judged = false;     // enough samples on both sides of the window's start
  bool roughening = false;
  int fromStep = 0, toStep = 0;
  double slopeBefore = 0, slopeAfter = 0;  // mean RMS slope of the samples before the window, and the last sample's
  double lossBefore = 0, lossAfter = 0;    // mean loss of the samples before the window, and of the window's
  std::string text;        // one sentence for the log
};
RougheningVerdict judgeRoughening(const std::vector<SurfaceWatchSample>& samples, int learnFrom, const RougheningRule& rule = {});

nlohmann::json surfaceWatchJson(const std::vector<SurfaceWatchSample>& samples);
std::vector<SurfaceWatchSample> surfaceWatchFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json rougheningJson(const RougheningVerdict& verdict);

}  // namespace refrax
