#include "engine/train/model_sizing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/run/train_config.h"

namespace refrax {

const std::vector<std::string>& sizedConfigKeys() {
  static const std::vector<std::string> keys = {"initial_gaussians", "max_gaussians", "mlp_octaves", "grid_cells", "subdivision_levels"};
  return keys;
}

namespace {

// Where the ray through pixel position (u, v) (pixel centres at integer + 0.5), through the
// camera's lens, meets the plane z = h; false when it runs parallel to it or away from it.
bool pixelOnPlane(const Camera& c, double u, double v, double h, glm::dvec3& at) {
  const glm::dvec3 d = c.rayDirection(u, v);
  const glm::dvec3 o = c.position();
  if (std::abs(d.z) < 1e-12) return false;
  const double t = (h - o.z) / d.z;
  if (!(t > 0)) return false;
  at = o + t * d;
  return true;
}

bool inside(const Rect& r, const glm::dvec3& p) { return p.x >= r.xMin && p.x <= r.xMax && p.y >= r.yMin && p.y <= r.yMax; }

std::string format(const char* f, double a = 0, double b = 0, double c = 0, double d = 0) {
  char text[320];
  std::snprintf(text, sizeof text, f, a, b, c, d);
  return text;
}

// Two significant figures: a count a person reads as chosen, not computed to the unit.
uint32_t roundCount(double x) {
  if (!(x >= 1)) return 1;
  const double scale = std::pow(10.0, std::floor(std::log10(x)) - 1);
  return uint32_t(std::lround(x / scale) * scale);
}

// Straight rays have no water to size, a flat or known water no height field.
bool sizesWater(WaterModel model, const std::string& key) {
  if (key == "initial_gaussians" || key == "max_gaussians") return true;
  if (model == WaterModel::NoRefraction) return false;
  return key != "mlp_octaves" || model == WaterModel::Refraction;
}

}  // namespace

double medianPixelFootprint(const std::vector<Camera>& cameras, double waterHeight, const Rect& domain) {
  constexpr int kSamples = 9;
  std::vector<double> sizes;
  for (const Camera& c : cameras)
    for (int j = 0; j < kSamples; j++)
      for (int i = 0; i < kSamples; i++) {
        const double u = (i + 0.5) * c.width / kSamples, v = (j + 0.5) * c.height / kSamples;
        glm::dvec3 p, pu, pv;
        if (!pixelOnPlane(c, u, v, waterHeight, p) || !inside(domain, p)) continue;
        if (!pixelOnPlane(c, u + 1, v, waterHeight, pu) || !pixelOnPlane(c, u, v + 1, waterHeight, pv)) continue;
        sizes.push_back(std::sqrt(glm::length(glm::cross(pu - p, pv - p))));
      }
  if (sizes.empty()) return 0;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  return sizes[sizes.size() / 2];
}

ModelSizing sizeModelFromData(const std::vector<Camera>& cameras, double waterHeight, const Rect& domain) {
  ModelSizing s;
  s.views = cameras.size();
  for (const Camera& c : cameras) s.pixelsPerView = std::max<uint64_t>(s.pixelsPerView, uint64_t(c.width) * uint64_t(c.height));
  s.pixelFootprint = medianPixelFootprint(cameras, waterHeight, domain);
  if (!(s.pixelFootprint > 0))
    fail("the model's size cannot be derived: no training view sees the water's domain (give --mlp-octaves, --grid-cells, --subdivision, "
         "--gaussians and --max-gaussians)");
  const double side = std::max(domain.xMax - domain.xMin, domain.yMax - domain.yMin);
  const double footprint = s.pixelFootprint;

  const double shortestWave = kResolvableWaveInPixels * footprint;
  const double octavesNeeded = 1 + std::ceil(std::log2(side / shortestWave) - 1e-9);
  s.mlpOctaves = uint32_t(std::clamp(octavesNeeded, double(kMinOctaves), double(kMaxOctaves)));
  s.gridCells = 1u << s.mlpOctaves;
  const double levels = std::round(std::log2(side / s.gridCells / (kFinestCellInPixels * footprint)));
  s.subdivisionLevels = uint32_t(std::clamp(levels, 0.0, double(kMaxSubdivision)));
  const double budget = double(s.pixelsPerView) / kPixelsPerGaussian;
  s.initialGaussians = roundCount(std::clamp(budget, double(kMinGaussians), double(kMaxGaussians)));
  s.maxGaussians = s.initialGaussians;

  const double finestPeriod = side / double(1u << (s.mlpOctaves - 1));
  s.choices = {
      {"initial_gaussians", double(s.initialGaussians),
       format("one per %.0f pixels of a %.0f-pixel training image (at least %.0f), the whole budget from the start", kPixelsPerGaussian,
              double(s.pixelsPerView), kMinGaussians)},
      {"max_gaussians", double(s.maxGaussians), "the initial count: densification refills what pruning frees"},
      {"mlp_octaves", double(s.mlpOctaves),
       format("finest period %.3g m (the %.3g m domain / 2^(octaves-1)), at most the shortest wave the views resolve: %.0f pixels of %.3g m "
              "on the water",
              finestPeriod, side, kResolvableWaveInPixels, footprint)},
      {"grid_cells", double(s.gridCells), format("2^octaves: two coarse vertices (MLP evaluations) per finest period of %.3g m", finestPeriod)},
      {"subdivision_levels", double(s.subdivisionLevels),
       format("finest triangles %.3g m, about %.0f pixels of %.3g m on the water", side / (s.gridCells << s.subdivisionLevels), kFinestCellInPixels,
              footprint)},
  };
  return s;
}

void applyModelSizing(TrainConfig& c, const std::vector<Camera>& trainCameras) {
  if (c.sizeFromData.empty()) return;
  const ModelSizing s = sizeModelFromData(trainCameras, c.waterHeight, c.domain);
  const bool coarseToFineOff = c.mlpCoarseOctaves >= c.mlpOctaves;
  nlohmann::json derived = nlohmann::json::object();
  for (const SizeChoice& choice : s.choices) {
    if (!c.sizeFromData.count(choice.key) || !sizesWater(c.model, choice.key)) continue;
    std::string reason = choice.reason;
    if (choice.key == "initial_gaussians") {
      c.initialGaussians = s.initialGaussians;
      if (!c.sizeFromData.count("max_gaussians") && c.initialGaussians > c.maxGaussians) {
        c.initialGaussians = c.maxGaussians;
        reason += "; lowered to the given --max-gaussians";
      }
    } else if (choice.key == "max_gaussians") {
      c.maxGaussians = std::max(s.maxGaussians, c.initialGaussians);
      if (c.maxGaussians != s.maxGaussians) reason += "; raised to the initial count";
    } else if (choice.key == "mlp_octaves") {
      c.mlpOctaves = s.mlpOctaves;
      if (coarseToFineOff) c.mlpCoarseOctaves = c.mlpOctaves;
    } else if (choice.key == "grid_cells") {
      c.gridCells = s.gridCells;
    } else if (choice.key == "subdivision_levels") {
      c.subdivisionLevels = s.subdivisionLevels;
    }
    const double value = choice.key == "initial_gaussians" ? c.initialGaussians : choice.key == "max_gaussians" ? c.maxGaussians : choice.value;
    derived[choice.key] = {{"value", value}, {"reason", reason}};
  }
  c.modelSizing = {{"pixel_footprint", s.pixelFootprint}, {"pixels_per_view", s.pixelsPerView}, {"views", s.views}, {"derived", derived}};
  c.sizeFromData.clear();
}

}  // namespace refrax
