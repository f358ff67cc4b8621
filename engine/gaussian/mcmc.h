#pragma once
// MCMC densification (3DGS-MCMC, Kheradmand et al. 2024; 3DGRUT and Brush offer it), on the
// host as engine/gaussian/densify.h: --densify-strategy mcmc. No clone, split, prune or
// density reset; instead, at the steps densifyDue names:
//
//   relocate  every Gaussian whose density is under minDensity ("dead") becomes a copy of a
//             live one, drawn with probability proportional to its density;
//   grow      the count grows by growFraction of itself, up to maxGaussians: the new rows are
//             copies of live ones drawn the same way (after the relocation);
//   share     a Gaussian copied so that it exists k times in all gives each copy the density
//             1 - (1 - o)^(1/k), so that the k copies stacked along a ray let through what the
//             one did, and its sigmas times mcmcSigmaFactor(o, k) (the paper's Eq. 9), so that
//             their summed footprint stays the one's.
//
// and at every step the means move by noise that only the nearly transparent feel
// (mcmcPositionNoise): what lets a dead Gaussian wander to where it can be useful. The copies
// and the sources they came from restart their Adam moments (rowMap kNewRow), as after a clone.
// Deterministic for a given rng state (own uniform and normal samplers).
#include <cstdint>
#include <random>
#include <vector>

#include "engine/gaussian/gaussians.h"

namespace refrax {

struct McmcConfig {
  float minDensity = 0.005f;   // dead below this (the paper's 0.005)
  float growFraction = 0.05f;  // per call (the paper's 5%)
  uint32_t maxGaussians = 1000000;
  // The noise's scale on top of the position learning rate (the paper's 5e5) and the gate's
  // sharpness: the noise is scaled by sigmoid(noiseSharpness * (minDensity - density)).
  float noiseScale = 5e5f;
  float noiseSharpness = 100.0f;
};
// The most copies one Gaussian shares its mass with at one call: the series of Eq. 9
// alternates, and in float-sized terms it stays exact to this count (the paper's 51).
constexpr int kMcmcMaxCopies = 51;

// The density each of k copies gets: 1 - (1 - o)^(1/k).
double mcmcSharedDensity(double density, int copies);
// The factor on each copy's sigmas (Eq. 9): o / sum_{i=1..k} sum_{j=0..i-1} C(i-1, j) (-1)^j
// o'^(j+1) / sqrt(j+1), with o' the shared density; 1 for k = 1.
double mcmcSigmaFactor(double density, int copies);

struct McmcStats {
  uint32_t before = 0, after = 0;
  uint32_t relocated = 0;  // dead rows that became copies
  uint32_t added = 0;      // rows appended by the growth
  double milliseconds = 0;
};

// Relocation then growth (nothing when no Gaussian is live). rowMap as densify's: one entry
// per output row, the old row it continues or kNewRow (the copies, and the rows they were
// copied from, whose density and sigmas changed).
McmcStats mcmcDensify(GaussianSet& set, const McmcConfig& config, std::mt19937& rng, std::vector<uint32_t>& rowMap);

// mean += positionLr * noiseScale * sigmoid(noiseSharpness * (minDensity - density)) * R S^2 R^T z,
// z ~ N(0, I) per Gaussian.
void mcmcPositionNoise(GaussianSet& set, const McmcConfig& config, double positionLr, std::mt19937& rng);

// Throws refrax::Error for a growth fraction outside [0, 1], densities outside [0, 1) or a
// negative noise.
void validateMcmcConfig(const McmcConfig& config);

}  // namespace refrax
