// nerfstudio dataset loader: one transforms.json as ns-process-data writes it (conventions in
// engine/dataset/dataset.h).
#include <algorithm>
#include <filesystem>
#include <set>

#include "engine/base/error.h"
#include "engine/dataset/dataset.h"
#include "engine/dataset/dataset_json.h"
#include "engine/dataset/transforms_frame.h"
#include "engine/dataset/water_frame.h"
#include "engine/io/atomic_file.h"
#include "engine/io/ply_points.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

std::string normalPath(const std::string& p) { return fs::path(p).lexically_normal().generic_string(); }

// The file paths a split list names (train_filenames, val_filenames, test_filenames), each one
// a frame's file_path; refrax::Error naming the list and the path otherwise.
std::set<std::string> listedFiles(const nlohmann::json& top, const char* key, const std::set<std::string>& frames, const std::string& where) {
  std::set<std::string> out;
  const nlohmann::json& list = top[key];
  if (!list.is_array()) fail(where + ": '" + key + "' must be an array of file paths");
  for (const nlohmann::json& name : list) {
    if (!name.is_string()) fail(where + ": '" + key + "' holds a value that is not a file path");
    const std::string n = normalPath(name.get<std::string>());
    if (!frames.count(n)) fail(where + ": '" + key + "' names " + name.get<std::string>() + ", which no frame's file_path is");
    out.insert(n);
  }
  return out;
}

// Which frames are test views: nerfstudio's test_filenames (else val_filenames) when given,
// train_filenames the training views (the rest when absent); else as LLFF and COLMAP.
std::vector<bool> testFlags(const nlohmann::json& top, const std::vector<View>& views, const DatasetOptions& options, const std::string& where) {
  std::set<std::string> frames;
  for (const View& v : views) frames.insert(normalPath(v.name));
  const char* testKey = top.contains("test_filenames") ? "test_filenames" : top.contains("val_filenames") ? "val_filenames" : nullptr;
  if (!testKey || !options.testViews.empty()) {
    std::vector<std::string> names;
    for (const View& v : views) names.push_back(v.name);
    return testViewFlags(names, options, where);
  }
  const std::set<std::string> test = listedFiles(top, testKey, frames, where);
  std::set<std::string> train;
  if (top.contains("train_filenames")) train = listedFiles(top, "train_filenames", frames, where);
  std::vector<bool> flags;
  for (const View& v : views) {
    const std::string n = normalPath(v.name);
    if (test.count(n) && train.count(n)) fail(where + ": " + v.name + " is in both train_filenames and " + testKey);
    flags.push_back(test.count(n) > 0);
  }
  if (std::count(flags.begin(), flags.end(), false) == 0) fail(where + ": every frame is a test view (" + testKey + ")");
  return flags;
}

// applied_transform is what ns-process-data turned its source's frame by; the poses (and
// sparse_pc.ply) already carry it, so it is only checked and noted.
void noteAppliedTransform(const nlohmann::json& top, const std::string& where, Dataset& d) {
  if (!top.contains("applied_transform")) return;
  const nlohmann::json& t = top["applied_transform"];
  bool ok = t.is_array() && (t.size() == 3 || t.size() == 4);
  for (size_t r = 0; ok && r < t.size(); r++) {
    ok = t[r].is_array() && t[r].size() == 4;
    for (size_t c = 0; ok && c < 4; c++) ok = t[r][c].is_number();
  }
  if (!ok) fail(where + ": 'applied_transform' must be a 3x4 or 4x4 array of numbers");
  d.notes.push_back("applied_transform (how ns-process-data turned its source's frame): the poses carry it already, so they are read as written");
}

}  // namespace

Dataset loadNerfstudioDataset(const std::string& folder, const DatasetOptions& options) {
  const std::string path = folder + "/transforms.json";
  const nlohmann::json top = readDatasetJson(path);
  if (!top.is_object()) fail(path + ": expected a JSON object");
  const nlohmann::json& frames = requireField(top, "frames", path);
  if (!frames.is_array()) fail(path + ": 'frames' must be an array");
  if (frames.size() < 2) fail(path + ": " + std::to_string(frames.size()) + " frames (at least 2 needed: one to train on, one to test)");
  Dataset d;
  d.root = folder;
  d.format = "nerfstudio";
  noteAppliedTransform(top, path, d);
  std::vector<View> views;
  for (size_t i = 0; i < frames.size(); i++) views.push_back(loadTransformsFrame(folder, frames[i], top, path + ": frame " + std::to_string(i), options, true));
  std::stable_sort(views.begin(), views.end(), [](const View& a, const View& b) { return a.name < b.name; });
  const std::vector<bool> test = testFlags(top, views, options, path);

  std::vector<PlyPoint> points;
  if (top.contains("ply_file_path")) {
    if (!top["ply_file_path"].is_string()) fail(path + ": 'ply_file_path' must be a string");
    points = readPlyPoints(folder + "/" + top["ply_file_path"].get<std::string>());
  }
  d.water = loadWaterMetadata(folder, options);
  if (!d.water.datasetFrame) {
    // The frame is the source's (COLMAP's, turned): derive the water's as for a COLMAP model.
    std::vector<glm::dmat4> poses;
    std::vector<glm::dvec3> positions;
    for (const View& v : views) poses.push_back(v.camera.cameraToWorld);
    for (const PlyPoint& p : points) positions.push_back(p.position);
    const WaterFrame frame = deriveWaterFrame(positions, poses, options, "the transforms.json frame", d);
    d.water = waterInFrame(folder, options, frame, "nerfstudio dataset " + folder, d);
    for (View& v : views) v.camera.cameraToWorld = poseInWaterFrame(v.camera.cameraToWorld, frame, d);
  } else if (options.up) {
    fail("--up: " + folder + "/water.json says its values are in the dataset's own frame (\"frame\": \"dataset\"), which is then used as it is");
  }
  for (const PlyPoint& p : points) d.points.push_back({glm::dvec3(d.normalization * glm::dvec4(p.position, 1)), p.colour});
  for (size_t i = 0; i < views.size(); i++) d.splits[test[i] ? "test" : "train"].push_back(std::move(views[i]));
  noteMasks(d);
  return d;
}

}  // namespace refrax
