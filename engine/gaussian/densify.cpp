#include "engine/gaussian/densify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/gaussian/densify_split.h"
#include "engine/gaussian/gaussian_math.h"

namespace refrax {
namespace {

bool stepCondition(uint32_t step, uint32_t from, uint32_t until, uint32_t interval) {
  return step >= from && step <= until && interval > 0 && step % interval == 0;
}

float largestSigma(const float* g) {
  const float* s = g + f32::kGaussLogScale;
  return f32::largestSigmaOf(glm::vec3(s[0], s[1], s[2]));
}

// Child `child` of the split of row `row`: mean drawn from N(mean, R S^2 R^T) with the
// counter-based normals of densify_split.glsl (the device's draws), sigmas divided by `divisor`.
void writeSplitChild(const float* parent, float* child, double divisor, uint32_t key, uint32_t row, uint32_t c) {
  std::copy(parent, parent + kGaussianFloats, child);
  const float* q = parent + f32::kGaussRotation;
  const float* ls = parent + f32::kGaussLogScale;
  glm::dvec3 offset = f64::splitChildOffset(glm::dvec4(q[0], q[1], q[2], q[3]), glm::dvec3(ls[0], ls[1], ls[2]), key, row, c);
  for (int a = 0; a < 3; a++) {
    child[f32::kGaussMean + a] = float(double(parent[f32::kGaussMean + a]) + offset[a]);
    child[f32::kGaussLogScale + a] = float(double(parent[f32::kGaussLogScale + a]) - std::log(divisor));
  }
}

}  // namespace

void validateDensifyConfig(const DensifyConfig& c) {
  if (!(c.sceneExtent > 0) || !std::isfinite(c.sceneExtent)) fail("densify: the scene extent must be positive");
  if (c.densifyInterval == 0 || c.pruneInterval == 0 || c.resetInterval == 0 || c.decayInterval == 0)
    fail("densify: every interval must be at least 1 step");
  if (!(c.gradThreshold > 0) || !(c.percentDense > 0) || !(c.pruneLargeFraction > 0))
    fail("densify: the gradient threshold, percentDense and pruneLargeFraction must be positive");
  if (!(c.splitScaleDivisor > 1)) fail("densify: splitScaleDivisor must exceed 1 (children smaller than the parent)");
  if (!(c.minDensity >= 0 && c.minDensity < 1)) fail("densify: minDensity must be in [0, 1)");
  if (!(c.resetDensity > 0 && c.resetDensity < 1)) fail("densify: resetDensity must be in (0, 1)");
  if (!(c.decayFactor > 0 && c.decayFactor <= 1)) fail("densify: decayFactor must be in (0, 1]");
  if (!(c.decayFloor >= 0 && c.decayFloor < 1)) fail("densify: decayFloor must be in [0, 1)");
  if (c.maxGaussians == 0) fail("densify: maxGaussians must be at least 1");
}

bool densifyDue(const DensifyConfig& c, uint32_t step) { return stepCondition(step, c.densifyFrom, c.densifyUntil, c.densifyInterval); }
bool pruneDue(const DensifyConfig& c, uint32_t step) { return stepCondition(step, c.pruneFrom, c.pruneUntil, c.pruneInterval); }
bool densityResetDue(const DensifyConfig& c, uint32_t step) { return stepCondition(step, c.resetFrom, c.resetUntil, c.resetInterval); }
bool densityDecayDue(const DensifyConfig& c, uint32_t step) { return stepCondition(step, c.decayFrom, c.decayUntil, c.decayInterval); }

float densifyStatistic(const std::vector<float>& stats, size_t i) {
  float hits = stats[2 * i + 1];
  return hits > 0 ? stats[2 * i] / hits : 0.0f;
}

DensifyStats densify(GaussianSet& set, const std::vector<float>& stats, const DensifyConfig& config, uint32_t step,
                     std::mt19937& rng, std::vector<uint32_t>& rowMap) {
  auto start = std::chrono::steady_clock::now();
  validateDensifyConfig(config);
  const size_t n = set.count();
  if (set.params.size() != n * kGaussianFloats) fail("densify: parameter count is not a multiple of " + std::to_string(kGaussianFloats));
  if (stats.size() != 2 * n)
    fail("densify: " + std::to_string(stats.size()) + " statistics for " + std::to_string(n) + " Gaussians (2 per Gaussian expected)");
  DensifyStats out;
  out.before = uint32_t(n);

  // 0 keep, 1 pruned (low density), 2 pruned (too large), 3 split (replaced by children).
  std::vector<uint8_t> fate(n, 0);
  if (pruneDue(config, step)) {
    const double minLogit = config.minDensity > 0 ? densityLogit(config.minDensity) : -INFINITY;
    const bool pruneLarge = step >= config.pruneLargeFromStep;
    const float largeLimit = config.pruneLargeFraction * config.sceneExtent;
    for (size_t i = 0; i < n; i++) {
      const float* g = set.at(i);
      if (double(g[f32::kGaussLogitDensity]) < minLogit) fate[i] = 1, out.prunedLowDensity++;
      else if (pruneLarge && largestSigma(g) > largeLimit) fate[i] = 2, out.prunedLarge++;
    }
  }
  size_t count = n - out.prunedLowDensity - out.prunedLarge;

  std::vector<uint32_t> clones, splits;
  if (densifyDue(config, step)) {
    std::vector<uint32_t> candidates;
    for (size_t i = 0; i < n; i++)
      if (fate[i] == 0 && densifyStatistic(stats, i) >= config.gradThreshold) candidates.push_back(uint32_t(i));
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](uint32_t a, uint32_t b) { return densifyStatistic(stats, a) > densifyStatistic(stats, b); });
    const float cloneLimit = config.percentDense * config.sceneExtent;
    for (uint32_t i : candidates) {
      if (count + 1 > config.maxGaussians) {  // a clone and a split both add one row
        out.cappedOut++;
        continue;
      }
      count++;
      if (largestSigma(set.at(i)) <= cloneLimit) clones.push_back(i);
      else splits.push_back(i), fate[i] = 3;
    }
    std::sort(clones.begin(), clones.end());
    std::sort(splits.begin(), splits.end());
  }
  out.cloned = uint32_t(clones.size());
  out.split = uint32_t(splits.size());

  GaussianSet next;
  next.params.reserve(count * kGaussianFloats);
  rowMap.clear();
  rowMap.reserve(count);
  for (size_t i = 0; i < n; i++)
    if (fate[i] == 0) {
      next.params.insert(next.params.end(), set.at(i), set.at(i) + kGaussianFloats);
      rowMap.push_back(uint32_t(i));
    }
  for (uint32_t i : clones) {
    next.params.insert(next.params.end(), set.at(i), set.at(i) + kGaussianFloats);
    rowMap.push_back(kNewRow);
  }
  // One draw per densification that may split, as the device's (densify_device.h) draws it.
  const uint32_t key = densifyDue(config, step) ? uint32_t(rng()) : 0u;
  for (uint32_t i : splits)
    for (uint32_t c = 0; c < 2; c++) {
      next.params.resize(next.params.size() + kGaussianFloats);
      writeSplitChild(set.at(i), next.params.data() + next.params.size() - kGaussianFloats, config.splitScaleDivisor, key, i, c);
      rowMap.push_back(kNewRow);
    }
  set = std::move(next);
  out.after = uint32_t(set.count());
  out.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

double densityLogit(double density) { return std::log(density / (1.0 - density)); }

void densityReset(GaussianSet& set, const DensifyConfig& config) {
  validateDensifyConfig(config);
  const float limit = float(densityLogit(config.resetDensity));
  for (size_t i = 0; i < set.count(); i++) {
    float& x = set.at(i)[f32::kGaussLogitDensity];
    x = std::min(x, limit);
  }
}

void densityDecay(GaussianSet& set, const DensifyConfig& config) {
  validateDensifyConfig(config);
  const double floorLogit = config.decayFloor > 0 ? densityLogit(config.decayFloor) : -1e30;
  for (size_t i = 0; i < set.count(); i++) {
    float& x = set.at(i)[f32::kGaussLogitDensity];
    x = float(f64::decayedLogit(double(x), double(config.decayFactor), floorLogit));
  }
}

}  // namespace refrax
