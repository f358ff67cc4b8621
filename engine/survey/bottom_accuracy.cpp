#include "engine/survey/bottom_accuracy.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/dataset/ground_truth.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// water.json's "bottom", or null.
nlohmann::json bottomEntry(const Dataset& d) {
  const fs::path water = fs::path(d.root) / "water.json";
  if (d.root.empty() || !fs::exists(water)) return nullptr;
  nlohmann::json w = readJson(water.string());
  return w.contains("bottom") ? w["bottom"] : nlohmann::json(nullptr);
}

nlohmann::json missing(const std::string& why) { return {{"bottom_truth_missing", why}}; }

// The water-free orthophoto against the truth's (north up: PNG row r is grid row ny - 1 - r),
// over the vertices a training view sees (nothing was learned of the rest).
double orthoPsnr(const BottomMaps& maps, const Image& truth) {
  const BottomGrid& g = maps.grid;
  double se = 0;
  size_t n = 0;
  for (uint32_t r = 0; r < g.ny; r++)
    for (uint32_t i = 0; i < g.nx; i++) {
      const size_t k = size_t(g.ny - 1 - r) * g.nx + i;
      if (maps.views[k] < 1) continue;
      for (int c = 0; c < 3; c++) {
        const double e = double(maps.orthoDry[3 * k + c]) - truth.pixels[3 * (size_t(r) * g.nx + i) + c];
        se += e * e, n++;
      }
    }
  const double mse = se / double(std::max<size_t>(n, 1));
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 100.0;
}

}  // namespace

uint32_t bottomTruthSize(const Dataset& d) {
  const nlohmann::json b = bottomEntry(d);
  if (b.is_null() || !b.contains("shape") || !b["shape"].is_array() || b["shape"].empty()) return 0;
  return b["shape"][0].get<uint32_t>();
}

nlohmann::json bottomAccuracy(const BottomMaps& maps, const Dataset& d) {
  const nlohmann::json b = bottomEntry(d);
  if (b.is_null()) return missing("the dataset has no truth under the water (water.json names no \"bottom\")");
  const BottomGrid& g = maps.grid;
  const fs::path root(d.root);
  const NpyArray truth = readNpy((root / b["elevation"].get<std::string>()).string());
  if (truth.shape != std::vector<size_t>{g.ny, g.nx})
    return missing("the truth's grid is " + std::to_string(truth.shape.empty() ? 0 : truth.shape[0]) + " vertices per side, the map's " +
                   std::to_string(g.nx) + " x " + std::to_string(g.ny) + " (export with --grid set to the truth's)");
  const Rect& t = d.water.domain ? *d.water.domain : g.box;
  if (t.xMin != g.box.xMin || t.yMin != g.box.yMin || t.xMax != g.box.xMax || t.yMax != g.box.yMax)
    return missing("the truth lies over the dataset's domain, the map over another");
  const std::optional<HeightGrid> surface = loadGroundTruthSurface(d);
  double se = 0, sum = 0, depthSum = 0;
  size_t cells = 0, seen = 0;
  for (uint32_t j = 0; j < g.ny; j++)
    for (uint32_t i = 0; i < g.nx; i++) {
      const size_t k = size_t(j) * g.nx + i;
      if (!std::isfinite(truth.data[k]) || maps.views[k] < 1) continue;
      seen++;
      if (!std::isfinite(maps.bottom[k])) continue;
      const double e = double(maps.bottom[k]) - truth.data[k];
      se += e * e, sum += e, cells++;
      depthSum += (surface ? sampleHeight(*surface, g.x(i), g.y(j)) : d.water.height.value_or(0.0)) - truth.data[k];
    }
  if (seen == 0) return missing("no vertex with a true bottom is seen by a training view");
  nlohmann::json m = {{"bottom_cells", cells}, {"bottom_coverage", double(cells) / double(seen)}};
  if (cells > 0) {
    const double rmse = std::sqrt(se / double(cells)), bias = sum / double(cells), depth = depthSum / double(cells);
    m["bottom_rmse_m"] = rmse, m["bottom_bias_m"] = bias, m["mean_true_depth_m"] = depth;
    if (depth > 0) m["bottom_rmse_share"] = rmse / depth, m["bottom_bias_share"] = bias / depth;
  }
  const Image ortho = readPng((root / b["orthophoto"].get<std::string>()).string());
  if (ortho.width == int(g.nx) && ortho.height == int(g.ny) && ortho.channels == 3) m["ortho_dry_psnr"] = orthoPsnr(maps, ortho);
  return m;
}

}  // namespace refrax
