#pragma once
// The mapped bottom against the truth a synthetic dataset carries (refrax synth's
// bottom_gt_height.npy and bottom_gt_ortho.png, named in water.json's "bottom"; the layout
// engine/synth/bottom_truth.h documents), over the cells where both have data:
//   bottom_rmse_m, bottom_bias_m (mapped minus true: > 0 is a bed mapped too high)
//   bottom_rmse_share, bottom_bias_share (of the mean true water depth over those cells)
//   bottom_coverage (the share of the cells with a true bottom that training views see which
//     the map covers), bottom_cells
//   ortho_dry_psnr (the water-free orthophoto against the true one, where training views see)
// or, where these cannot be computed, "bottom_truth_missing" with the reason.
#include <nlohmann/json.hpp>

#include "engine/dataset/dataset.h"
#include "engine/survey/bottom_maps.h"

namespace refrax {

// The truth's grid size (vertices per side) where the dataset has one, else 0.
uint32_t bottomTruthSize(const Dataset& dataset);

nlohmann::json bottomAccuracy(const BottomMaps& maps, const Dataset& dataset);

}  // namespace refrax
