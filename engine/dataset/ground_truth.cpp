#include "engine/dataset/ground_truth.h"

#include "engine/dataset/dataset_json.h"
#include "engine/error.h"
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

}  // namespace refrax
