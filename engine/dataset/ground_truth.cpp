#include "engine/dataset/ground_truth.h"

#include <cmath>

#include "engine/dataset/dataset_json.h"
#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/npy.h"

namespace refrax {

HeightGrid loadHeightGridNpy(const std::string& path, const Rect& domain) {
  NpyArray a = readNpy(path);
  if (a.shape.size() != 2) fail(path + ": a height map must be a 2D array (ny, nx)");
  HeightGrid g;
  g.ny = int(a.shape[0]);
  g.nx = int(a.shape[1]);
  g.xMin = domain.xMin;
  g.yMin = domain.yMin;
  g.xMax = domain.xMax;
  g.yMax = domain.yMax;
  g.heights = a.data;
  try {
    validateHeightGrid(g);
  } catch (const Error& e) {
    fail(path + ": " + e.what());
  }
  return g;
}

std::optional<HeightGrid> loadGroundTruthSurface(const Dataset& d) {
  const std::string path = d.root + "/water.json";
  if (!fileExists(path)) return std::nullopt;
  nlohmann::json j = readDatasetJson(path);
  if (!j.is_object() || !j.contains("height_map")) return std::nullopt;
  std::optional<Rect> domain = d.water.domain;
  // `refrax synth` writes the object form {"file": ..., "domain": [xmin, ymin, xmax, ymax], ...}.
  const nlohmann::json& map = j["height_map"];
  if (map.is_object()) {
    if (!map.contains("file") || !map["file"].is_string()) fail(path + ": 'height_map' must name its 'file'");
    if (map.contains("domain")) {
      const auto& v = map["domain"];
      if (!v.is_array() || v.size() != 4 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number() || !v[3].is_number())
        fail(path + ": 'height_map' 'domain' must be [xmin, ymin, xmax, ymax]");
      domain = Rect{v[0].get<double>(), v[1].get<double>(), v[2].get<double>(), v[3].get<double>()};
    }
    if (!domain) fail(path + ": 'height_map' needs a 'domain'");
    return loadHeightGridNpy(d.root + "/" + map["file"].get<std::string>(), *domain);
  }
  if (!map.is_string()) fail(path + ": 'height_map' must be a file name");
  if (j.contains("height_map_domain")) {
    const auto& v = j["height_map_domain"];
    if (!v.is_array() || v.size() != 4 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number() || !v[3].is_number())
      fail(path + ": 'height_map_domain' must be [xmin, ymin, xmax, ymax]");
    domain = Rect{v[0].get<double>(), v[1].get<double>(), v[2].get<double>(), v[3].get<double>()};
  }
  if (!domain) fail(path + ": 'height_map' needs 'height_map_domain' or 'domain'");
  return loadHeightGridNpy(d.root + "/" + j["height_map"].get<std::string>(), *domain);
}

AnalyticWaves loadGroundTruthWaves(const Dataset& d) {
  const std::string path = d.root + "/water.json";
  const std::string what = path + ": the known-water oracle needs ";
  if (!fileExists(path)) fail(what + "a water.json with the ground-truth 'surface'");
  nlohmann::json j = readDatasetJson(path);
  if (!j.is_object() || !j.contains("surface") || !j["surface"].is_object()) fail(what + "a ground-truth 'surface'");
  const nlohmann::json& s = j["surface"];
  if (s.value("type", "") != "wave_sum") fail(what + "a 'surface' of type 'wave_sum'");
  const nlohmann::json none = nlohmann::json::array();
  const nlohmann::json& waves = s.contains("directional_waves") ? s["directional_waves"] : none;
  const nlohmann::json& ripples = s.contains("radial_ripples") ? s["radial_ripples"] : none;
  if (!waves.is_array() || !ripples.is_array()) fail(path + ": 'directional_waves' and 'radial_ripples' must be arrays");
  if (waves.size() + ripples.size() > 4) fail(what + "at most 4 directional waves and radial ripples together");
  if (d.normalization != glm::dmat4(1.0)) fail(what + "a dataset in its own world frame (this one is normalised on loading)");
  auto number = [&](const nlohmann::json& o, const char* key) {
    if (!o.is_object() || !o.contains(key) || !o[key].is_number() || !std::isfinite(o[key].get<double>()))
      fail(path + ": surface wave '" + key + "' must be a finite number");
    return o[key].get<double>();
  };
  AnalyticWaves w;
  w.base = float(number(s, "mean_height"));
  size_t k = 0;
  for (const auto& wave : waves) {
    w.waves[k][0] = float(number(wave, "amplitude"));
    w.waves[k][1] = float(number(wave, "kx"));
    w.waves[k][2] = float(number(wave, "ky"));
    w.waves[k][3] = float(number(wave, "phase"));
    k++;
  }
  for (const auto& ripple : ripples) {  // after the sines: a component is a ripple by its sigma
    w.waves[k][0] = float(number(ripple, "amplitude"));
    w.waves[k][1] = float(number(ripple, "cx"));
    w.waves[k][2] = float(number(ripple, "cy"));
    w.waves[k][3] = float(number(ripple, "k"));
    w.sigma[k] = float(number(ripple, "sigma"));
    if (!(w.sigma[k] > 0)) fail(path + ": a radial ripple's 'sigma' must be positive");
    k++;
  }
  return w;
}

KnownWaterTruth loadKnownWater(const Dataset& d) {
  KnownWaterTruth truth;
  try {
    truth.waves = loadGroundTruthWaves(d);
  } catch (const Error&) {
    std::optional<HeightGrid> grid = loadGroundTruthSurface(d);  // its own error for a map that is wrong
    if (!grid) throw;                                             // neither: the closed form's reason
    if (d.normalization != glm::dmat4(1.0))
      fail(d.root + "/water.json: the known-water oracle needs a dataset in its own world frame (this one is normalised on loading)");
    truth.grid = std::move(grid);
  }
  return truth;
}

void scaleKnownWater(KnownWaterTruth& truth, double scale) {
  if (truth.waves)
    for (auto& wave : truth.waves->waves) wave[0] = float(wave[0] * scale);  // a sine's or a ripple's amplitude
  if (truth.grid && !truth.grid->heights.empty()) {
    std::vector<double>& h = truth.grid->heights;
    double mean = 0;
    for (double v : h) mean += v;
    mean /= double(h.size());
    for (double& v : h) v = mean + scale * (v - mean);
  }
}

}  // namespace refrax
