#pragma once
// The ground-truth water surface for evaluation, when a dataset has one: a height map stored
// as an .npy array of shape (ny, nx) (row j at y = ymin + j (ymax - ymin) / (ny - 1), column i
// likewise in x), named in water.json as "height_map" (a path relative to the dataset folder)
// with its domain "height_map_domain": [xmin, ymin, xmax, ymax] (default: "domain").
#include <optional>
#include <string>

#include "engine/height/analytic_height.h"
#include "engine/dataset/dataset.h"
#include "engine/loss/metrics.h"

namespace refrax {

HeightGrid loadHeightGridNpy(const std::string& path, const Rect& domain);
// The dataset's ground-truth height grid, or nothing when water.json names none.
std::optional<HeightGrid> loadGroundTruthSurface(const Dataset& dataset);
// The closed-form ground-truth surface of water.json ("surface": {"type": "wave_sum",
// "mean_height", "directional_waves": [{amplitude, kx, ky, phase}], "radial_ripples": []},
// "radial_ripples": [{amplitude, cx, cy, k, sigma}]}, as `refrax synth` writes it) for the
// known-water oracle. refrax::Error when the dataset has none, or a surface AnalyticWaves cannot
// hold (more than 4 waves and ripples together).
AnalyticWaves loadGroundTruthWaves(const Dataset& dataset);

// The known-water oracle's water: the closed form where AnalyticWaves holds it (exact); else,
// where water.json names a height map (every dataset refrax synth writes does), that grid,
// sampled bilinearly. refrax::Error (loadGroundTruthWaves') when the dataset has neither.
struct KnownWaterTruth {
  std::optional<AnalyticWaves> waves;
  std::optional<HeightGrid> grid;
};
KnownWaterTruth loadKnownWater(const Dataset& dataset);
// The relief scaled about the level by `scale` (0: flat): the waves' and ripples' amplitudes
// (the base kept), or the height map about its mean height.
void scaleKnownWater(KnownWaterTruth& truth, double scale);

}  // namespace refrax
