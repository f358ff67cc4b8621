#pragma once
// Adaptive density control of the Gaussians (3DGS strategy as 3DGRT and RefracGS run it,
// docs/method.md §1.6), on the host: the trainer keeps the parameters and the tracer's
// statistics on the host, calls densify at the steps densifyDue/pruneDue name, remaps the
// Adam table with the returned row map (engine/optim/table_adam.h remapTableAdamRows), uploads
// the new set and zeroes the statistics; and decays and resets the densities
// (densityDecay/densityReset) at the steps densityDecayDue/densityResetDue name.
//
//   clone  a Gaussian whose mean statistic (sum of |dL/dmean| * distance / 2 over the rays
//          that blended it, divided by their number; the trainer scales dL/dmean by
//          densifyStatScale) is >= gradThreshold and whose largest
//          sigma is <= percentDense * sceneExtent: an exact copy is appended.
//   split  the same statistic, larger sigma: the Gaussian is replaced by 2 children with
//          means drawn from the parent's distribution N(mean, R S^2 R^T), sigmas / 1.6 and
//          the parent's rotation, density and colour, appended after the clones.
//   prune  density < minDensity; and from pruneLargeFromStep on (after the first density
//          reset, as 3DGS) a largest sigma > pruneLargeFraction * sceneExtent. A pruned
//          Gaussian is neither cloned nor split.
//   cap    maxGaussians bounds the result: candidates are taken by decreasing statistic
//          (ties: lower row first) while the count stays within the cap; pruning never
//          adds, so a set already over the cap only shrinks.
// Output order: surviving rows in their old order, then clones, then split children (two
// per parent, consecutive). Deterministic for a given rng state (own normal sampler, no
// std:: distribution whose output depends on the standard library).
#include <cstdint>
#include <random>
#include <vector>

#include "engine/optim/adam.h"  // kNewRow
#include "engine/gaussian/gaussians.h"

namespace refrax {

struct DensifyConfig {
  float sceneExtent = 1.0f;          // the radius 3DGS calls cameras_extent
  // Clone / split (synthetic defaults; real scenes: gradThreshold 1e-3, percentDense 0.01).
  uint32_t densifyFrom = 500, densifyUntil = 15000, densifyInterval = 300;
  float gradThreshold = 3e-4f;
  float percentDense = 0.015f;       // clone at most this * extent (largest sigma), split above
  float splitScaleDivisor = 1.6f;    // children's sigmas = parent's / this (3DGS: 0.8 * 2)
  // Prune.
  uint32_t pruneFrom = 500, pruneUntil = 15000, pruneInterval = 100;
  float minDensity = 0.005f;
  uint32_t pruneLargeFromStep = 3000;
  float pruneLargeFraction = 0.1f;   // of the scene extent (3DGS's world-space size test)
  uint32_t maxGaussians = 1000000;
  // Density reset and decay (densityReset / densityDecay; when is the trainer's call).
  uint32_t resetFrom = 3000, resetUntil = 15000, resetInterval = 3000;
  float resetDensity = 0.01f;
  uint32_t decayFrom = 0, decayUntil = 0xFFFFFFFFu, decayInterval = 50;
  float decayFactor = 0.99f;
  // The density the decay leaves every Gaussian at or above (0: none). Training keeps 1e-6, so
  // a Gaussian the optimiser drove toward zero stays where Adam can bring it back.
  float decayFloor = 0.0f;
};
// The factor the trainer applies to a step's gradient statistic: the loss is the mean over the
// batch's rays, so |dL/dmean| per ray falls as 1/rays, and a threshold that densifies 32 x 32
// patches (1,024 rays, where 3e-4 was set) would starve 128 x 128 patches (16x smaller) and
// whole 392 x 392 images (150x); docs/experiments/2026-11-27-dry-fit-patches.md. Scaled by
// rays / 1,024, the statistic reads as on a 32 x 32 patch for any batch.
inline float densifyStatScale(uint32_t batchRays) { return float(batchRays) / 1024.0f; }

// Throws refrax::Error for non-positive extent, intervals or divisor, or thresholds out of range.
void validateDensifyConfig(const DensifyConfig& config);

// Step conditions as 3DGRT's check_step_condition: from <= step <= until and step % interval == 0.
bool densifyDue(const DensifyConfig& c, uint32_t step);
bool pruneDue(const DensifyConfig& c, uint32_t step);
bool densityResetDue(const DensifyConfig& c, uint32_t step);
bool densityDecayDue(const DensifyConfig& c, uint32_t step);

struct DensifyStats {
  uint32_t before = 0, after = 0;
  uint32_t cloned = 0;           // copies appended
  uint32_t split = 0;            // parents replaced by 2 children each
  uint32_t prunedLowDensity = 0;
  uint32_t prunedLarge = 0;
  uint32_t cappedOut = 0;        // candidates skipped to respect maxGaussians
  double milliseconds = 0;       // host time of the call
};

// Runs what is due at `step`: clone/split when densifyDue, prune when pruneDue (both when
// both are due; nothing when neither: rowMap is then the identity). `stats` holds 2 floats
// per Gaussian as the tracer accumulates them (GaussianGradients::stats: sum, ray count).
// rowMap[i] (one per output row) is the old row that row i continues, or kNewRow for a
// clone or split child, exactly what remapTableAdamRows takes: new rows start at zero moments.
DensifyStats densify(GaussianSet& set, const std::vector<float>& stats, const DensifyConfig& config, uint32_t step,
                     std::mt19937& rng, std::vector<uint32_t>& rowMap);

// The logit a density is stored as.
double densityLogit(double density);
// density = min(density, config.resetDensity) for every Gaussian (on the logits).
void densityReset(GaussianSet& set, const DensifyConfig& config);
// density = max(density * config.decayFactor, config.decayFloor) for every Gaussian (on the logits).
void densityDecay(GaussianSet& set, const DensifyConfig& config);

// The mean statistic of Gaussian i (0 when no ray blended it).
float densifyStatistic(const std::vector<float>& stats, size_t i);

}  // namespace refrax
