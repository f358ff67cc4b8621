#include "engine/surface/surface_watch.h"

#include <cmath>
#include <cstdio>

#include "engine/base/error.h"

namespace refrax {

SurfaceShape measureSurfaceShape(const std::vector<float>& heights, const GridLayout& g, const std::vector<double>& weights) {
  if (weights.size() != heights.size()) fail("measureSurfaceShape: the weights are not sized like the heights");
  auto slot = [&](uint32_t i, uint32_t j) { return g.first + size_t(j) * g.rowLength + i; };
  double w = 0, mean = 0;
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) {
      size_t k = slot(i, j);
      if (weights[k] > 0 && std::isfinite(heights[k])) {
        w += weights[k];
        mean += weights[k] * heights[k];
      }
    }
  SurfaceShape s;
  if (!(w > 0)) return s;
  mean /= w;
  double spread = 0, slopeSum = 0, slopeWeight = 0;
  auto edge = [&](size_t a, size_t b, double spacing) {
    if (!(weights[a] > 0 && weights[b] > 0 && std::isfinite(heights[a]) && std::isfinite(heights[b]))) return;
    double slope = (double(heights[a]) - double(heights[b])) / spacing, we = 0.5 * (weights[a] + weights[b]);
    slopeSum += we * slope * slope;
    slopeWeight += we;
  };
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) {
      size_t k = slot(i, j);
      if (!(weights[k] > 0 && std::isfinite(heights[k]))) continue;
      spread += weights[k] * (heights[k] - mean) * (heights[k] - mean);
      if (i < g.cellsX) edge(k, slot(i + 1, j), g.spacingX);
      if (j < g.cellsY) edge(k, slot(i, j + 1), g.spacingY);
    }
  s.heightRms = std::sqrt(spread / w);
  s.slopeRms = slopeWeight > 0 ? std::sqrt(slopeSum / slopeWeight) : 0.0;
  return s;
}

RougheningVerdict judgeRoughening(const std::vector<SurfaceWatchSample>& samples, int learnFrom, const RougheningRule& rule) {
  RougheningVerdict v;
  if (samples.empty()) return v;
  const int last = samples.back().step;
  const double span = double(last - learnFrom);
  if (!(span > 0)) return v;
  // The window: the last `window` of the learning; before it, a span as long.
  const double windowStart = last - rule.window * span, beforeStart = windowStart - rule.window * span;
  double slopeBefore = 0, lossBefore = 0, lossAfter = 0;
  int nBefore = 0, nAfter = 0;
  for (const SurfaceWatchSample& s : samples) {
    if (s.step <= learnFrom || s.step < beforeStart) continue;
    if (s.step < windowStart) {
      slopeBefore += s.shape.slopeRms;
      lossBefore += s.loss;
      nBefore++;
    } else {
      lossAfter += s.loss;
      nAfter++;
    }
  }
  if (nBefore < 2 || nAfter < 2) return v;
  v.judged = true;
  v.fromStep = int(std::lround(windowStart));
  v.toStep = last;
  v.slopeBefore = slopeBefore / nBefore;
  v.slopeAfter = samples.back().shape.slopeRms;
  v.lossBefore = lossBefore / nBefore;
  v.lossAfter = lossAfter / nAfter;
  const bool slopeGrew = v.slopeAfter > (1 + rule.slopeGrowth) * v.slopeBefore;
  const bool lossStalled = v.lossAfter > (1 - rule.lossFall) * v.lossBefore;
  v.roughening = slopeGrew && lossStalled;
  char text[400];
  std::snprintf(text, sizeof text,
                "%s: from step %d to %d the seen water's RMS slope went %.4g -> %.4g (%+.0f%%) while the mean training loss went %.5g -> "
                "%.5g (%+.1f%%)%s",
                v.roughening ? "the learned water roughened while the loss stalled" : "surface watch", v.fromStep,
                v.toStep, v.slopeBefore, v.slopeAfter, 100 * (v.slopeAfter / std::max(v.slopeBefore, 1e-30) - 1), v.lossBefore, v.lossAfter,
                100 * (v.lossAfter / std::max(v.lossBefore, 1e-30) - 1),
                v.roughening ? "; its heights may be further from the truth than the flat start (docs/training.md, \"A roughening surface\")" : "");
  v.text = text;
  return v;
}

nlohmann::json surfaceWatchJson(const std::vector<SurfaceWatchSample>& samples) {
  nlohmann::json a = nlohmann::json::array();
  for (const SurfaceWatchSample& s : samples)
    a.push_back({{"step", s.step}, {"loss", s.loss}, {"slope_rms", s.shape.slopeRms}, {"height_rms", s.shape.heightRms}});
  return a;
}

std::vector<SurfaceWatchSample> surfaceWatchFromJson(const nlohmann::json& j, const std::string& where) {
  std::vector<SurfaceWatchSample> samples;
  if (!j.is_array()) fail(where + ": not an array of surface samples");
  try {
    for (const auto& e : j) {
      SurfaceWatchSample s;
      s.step = e.at("step").get<int>();
      s.loss = e.at("loss").get<double>();
      s.shape.slopeRms = e.at("slope_rms").get<double>();
      s.shape.heightRms = e.at("height_rms").get<double>();
      samples.push_back(s);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(where + ": not an array of surface samples (" + e.what() + ")");
  }
  return samples;
}

nlohmann::json rougheningJson(const RougheningVerdict& v) {
  if (!v.judged) return {{"judged", false}};
  return {{"judged", true},          {"roughening", v.roughening}, {"from_step", v.fromStep},   {"to_step", v.toStep},
          {"slope_before", v.slopeBefore}, {"slope_after", v.slopeAfter}, {"loss_before", v.lossBefore}, {"loss_after", v.lossAfter},
          {"text", v.text}};
}

}  // namespace refrax
