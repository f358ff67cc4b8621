#pragma once
// The ground-truth water surface for evaluation, when a dataset has one: a height map stored
// as an .npy array of shape (ny, nx) (row j at y = ymin + j (ymax - ymin) / (ny - 1), column i
// likewise in x), named in water.json as "height_map" (a path relative to the dataset folder)
// with its domain "height_map_domain": [xmin, ymin, xmax, ymax] (default: "domain").
#include <optional>
#include <string>

#include "engine/dataset/dataset.h"
#include "engine/metrics.h"

namespace refrax {

HeightGrid loadHeightGridNpy(const std::string& path, const Rect& domain);
// The dataset's ground-truth height grid, or nothing when water.json names none.
std::optional<HeightGrid> loadGroundTruthSurface(const Dataset& dataset);

}  // namespace refrax
