// NeRF/Blender dataset loader (conventions in engine/dataset/dataset.h).
#include <cmath>
#include <filesystem>

#include "engine/dataset/dataset.h"
#include "engine/dataset/view_image.h"
#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/dataset/dataset_json.h"
#include "engine/dataset/transforms_frame.h"
#include "engine/io/json_io.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// The image a frame names: as written, or with one of the usual extensions appended.
std::string resolveImage(const std::string& folder, const std::string& filePath, const std::string& where) {
  std::string base = folder + "/" + filePath;
  if (fs::is_regular_file(base)) return base;
  for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG"})
    if (fs::is_regular_file(base + ext)) return base + ext;
  fail(where + ": image " + base + " does not exist (also tried .png, .jpg, .jpeg)");
}

double optionalNumber(const nlohmann::json& frame, const nlohmann::json& top, const char* key, const std::string& where, double fallback) {
  if (frame.is_object() && frame.contains(key)) return requireNumber(frame, key, where);
  if (top.contains(key)) return requireNumber(top, key, where);
  return fallback;
}

bool has(const nlohmann::json& frame, const nlohmann::json& top, const char* key) {
  return (frame.is_object() && frame.contains(key)) || top.contains(key);
}

// The lens a frame (or the file) names: camera_model and k1..k4, p1, p2 (engine/camera/lens.h).
Lens frameLens(const nlohmann::json& frame, const nlohmann::json& top, const std::string& where) {
  LensFields fields;
  if (has(frame, top, "camera_model")) {
    const nlohmann::json& model = frame.contains("camera_model") ? frame["camera_model"] : top["camera_model"];
    if (!model.is_string()) fail(where + ": 'camera_model' must be a string");
    fields.cameraModel = model.get<std::string>();
  }
  fields.k1 = optionalNumber(frame, top, "k1", where, 0);
  fields.k2 = optionalNumber(frame, top, "k2", where, 0);
  fields.k3 = optionalNumber(frame, top, "k3", where, 0);
  fields.k4 = optionalNumber(frame, top, "k4", where, 0);
  fields.p1 = optionalNumber(frame, top, "p1", where, 0);
  fields.p2 = optionalNumber(frame, top, "p2", where, 0);
  return lensFromTransformsFields(fields, where);
}

}  // namespace

View loadTransformsFrame(const std::string& folder, const nlohmann::json& f, const nlohmann::json& top, const std::string& where,
                         const DatasetOptions& options, bool maskPathField) {
  if (!f.is_object()) fail(where + ": expected a JSON object");
  const nlohmann::json& fp = requireField(f, "file_path", where);
  if (!fp.is_string()) fail(where + ": 'file_path' must be a string");
  const nlohmann::json& tm = requireField(f, "transform_matrix", where);
  glm::dmat4 c2w(1.0);
  if (!tm.is_array() || tm.size() != 4) fail(where + ": 'transform_matrix' must be a 4x4 array");
  for (int r = 0; r < 4; r++) {
    if (!tm[r].is_array() || tm[r].size() != 4) fail(where + ": 'transform_matrix' must be a 4x4 array");
    for (int c = 0; c < 4; c++) {
      if (!tm[r][c].is_number()) fail(where + ": 'transform_matrix' holds a value that is not a number");
      c2w[c][r] = tm[r][c].get<double>();  // JSON is row-major, glm column-major
    }
  }
  validateCameraToWorld(c2w, where);

  View v;
  v.name = fp.get<std::string>();
  int expectW = int(optionalNumber(f, top, "w", where, 0)), expectH = int(optionalNumber(f, top, "h", where, 0));
  const std::string imagePath = resolveImage(folder, v.name, where);
  v.image = loadViewImage(imagePath, expectW, expectH, options.background, where);
  if (maskPathField && f.contains("mask_path")) {  // nerfstudio's: the frame names its mask, which must then exist
    const nlohmann::json& mp = f["mask_path"];
    if (!mp.is_string()) fail(where + ": 'mask_path' must be a string");
    const std::string maskPath = resolveImage(folder, mp.get<std::string>(), where);
    v.mask = loadViewMask(imagePath, maskPath, v.image.width, v.image.height, where);
  } else {
    // masks/<file_path>.png: "./train/000" -> masks/train/000.png
    const std::string relative = fs::path(v.name).lexically_normal().generic_string();
    v.mask = loadViewMask(imagePath, folder + "/masks/" + replaceExtension(relative, ".png"), v.image.width, v.image.height, where);
  }
  Camera& cam = v.camera;
  cam.cameraToWorld = c2w;
  cam.width = v.image.width;
  cam.height = v.image.height;
  if (has(f, top, "fl_x")) {
    cam.fx = optionalNumber(f, top, "fl_x", where, 0);
    cam.fy = optionalNumber(f, top, "fl_y", where, cam.fx);
  } else if (has(f, top, "camera_angle_x")) {
    double ax = optionalNumber(f, top, "camera_angle_x", where, 0);
    cam.fx = 0.5 * cam.width / std::tan(0.5 * ax);
    cam.fy = has(f, top, "camera_angle_y") ? 0.5 * cam.height / std::tan(0.5 * optionalNumber(f, top, "camera_angle_y", where, 0)) : cam.fx;
  } else {
    fail(where + ": no intrinsics (need camera_angle_x, or fl_x)");
  }
  cam.cx = optionalNumber(f, top, "cx", where, 0.5 * cam.width);
  cam.cy = optionalNumber(f, top, "cy", where, 0.5 * cam.height);
  if (!(cam.fx > 0) || !(cam.fy > 0) || !std::isfinite(cam.fx) || !std::isfinite(cam.fy))
    fail(where + ": the focal length is not a positive finite number");
  cam.lens = frameLens(f, top, where);
  checkLensCoversImage(cam, where);
  return v;
}

namespace {

std::vector<View> loadSplit(const std::string& folder, const std::string& file, const DatasetOptions& options) {
  const std::string path = folder + "/" + file;
  nlohmann::json top = readDatasetJson(path);
  if (!top.is_object()) fail(path + ": expected a JSON object");
  const nlohmann::json& frames = requireField(top, "frames", path);
  if (!frames.is_array()) fail(path + ": 'frames' must be an array");
  if (frames.empty()) fail(path + ": the split has no frames");
  std::vector<View> views;
  for (size_t i = 0; i < frames.size(); i++) {
    const std::string where = path + ": frame " + std::to_string(i);
    // A Blender split's mask_path is not a loss mask (refrax synth writes its water-coverage
    // masks there); nerfstudio's transforms.json's is.
    View v = loadTransformsFrame(folder, frames[i], top, where, options, false);
    const int expectW = int(optionalNumber(frames[i], top, "w", where, 0));
    // every view of a split has the size of the first unless w/h say otherwise
    if (!views.empty() && expectW == 0 && (v.image.width != views[0].image.width || v.image.height != views[0].image.height))
      fail(where + ": image is " + std::to_string(v.image.width) + "x" + std::to_string(v.image.height) + ", the split's first is " +
           std::to_string(views[0].image.width) + "x" + std::to_string(views[0].image.height));
    views.push_back(std::move(v));
  }
  return views;
}

}  // namespace

Dataset loadBlenderDataset(const std::string& folder, const DatasetOptions& options) {
  Dataset d;
  d.root = folder;
  d.format = "blender";
  if (!fileExists(folder + "/transforms_train.json")) fail("no transforms_train.json in " + folder);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    std::string name = entry.path().filename().string();
    const std::string prefix = "transforms_", suffix = ".json";
    if (name.size() > prefix.size() + suffix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      std::string split = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
      d.splits[split] = loadSplit(folder, name, options);
    }
  }
  d.water = loadWaterMetadata(folder, options);
  noteMasks(d);
  return d;
}

}  // namespace refrax
