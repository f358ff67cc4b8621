#include <cmath>

#include "engine/dataset/dataset.h"
#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/dataset/dataset_json.h"
#include "engine/io/json_io.h"

namespace refrax {

WaterMetadata loadWaterMetadata(const std::string& folder, const DatasetOptions& options) {
  WaterMetadata w;
  const std::string path = folder + "/water.json";
  if (fileExists(path)) {
    nlohmann::json j = readDatasetJson(path);
    if (!j.is_object()) fail(path + ": expected a JSON object");
    if (j.contains("frame")) {
      if (!j["frame"].is_string() || (j["frame"] != "loaded" && j["frame"] != "dataset"))
        fail(path + ": 'frame' must be \"loaded\" (the loader's frame, the default) or \"dataset\" (the poses' own frame)");
      w.datasetFrame = j["frame"] == "dataset";
    }
    if (j.contains("ior")) w.ior = requireNumber(j, "ior", path);
    if (j.contains("height")) w.height = requireNumber(j, "height", path);
    // `refrax synth` writes the mean water level as "mean_height"
    else if (j.contains("mean_height")) w.height = requireNumber(j, "mean_height", path);
    if (j.contains("depth")) w.depth = requireNumber(j, "depth", path);
    if (j.contains("domain")) {
      const auto& d = j["domain"];
      if (!d.is_array() || d.size() != 4) fail(path + ": 'domain' must be [xmin, ymin, xmax, ymax]");
      double v[4];
      for (int i = 0; i < 4; i++) {
        if (!d[i].is_number() || !std::isfinite(d[i].get<double>())) fail(path + ": 'domain' must hold four finite numbers");
        v[i] = d[i].get<double>();
      }
      w.domain = Rect{v[0], v[1], v[2], v[3]};
    }
  }
  // Each value is checked where it came from: the file, or the flag that overrides it.
  auto from = [&](bool flag, const char* name) { return flag ? std::string(name) : path; };
  if (options.ior) w.ior = *options.ior;
  if (options.waterHeight) w.height = *options.waterHeight;
  if (options.waterDepth) w.depth = *options.waterDepth;
  if (options.domain) w.domain = *options.domain;
  if (!validIor(w.ior))
    fail(from(options.ior.has_value(), "--ior") + ": the index of refraction must be " + kIorRange + ", got " + std::to_string(w.ior));
  if (w.height && !std::isfinite(*w.height)) fail(from(options.waterHeight.has_value(), "--water-height") + ": the water height is not finite");
  if (w.depth && !(*w.depth > 0 && std::isfinite(*w.depth)))
    fail(from(options.waterDepth.has_value(), "--water-depth") + ": the water depth must be a positive number");
  if (w.domain && !(w.domain->xMax > w.domain->xMin && w.domain->yMax > w.domain->yMin))
    fail(from(options.domain.has_value(), "--domain") + ": the surface domain is empty (need xmin < xmax and ymin < ymax)");
  return w;
}

}  // namespace refrax
