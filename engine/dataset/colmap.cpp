// COLMAP dataset loader: a sparse model (engine/dataset/colmap_model.h) and its images, in a
// frame derived for the water (documented in engine/dataset/dataset.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/dataset/dataset.h"
#include "engine/dataset/view_image.h"
#include "engine/dataset/water_frame.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// The model folder: sparse/0, sparse, or the dataset folder itself.
std::string modelFolder(const std::string& folder) {
  for (const std::string& f : {folder + "/sparse/0", folder + "/sparse", folder})
    if (hasColmapModel(f)) return f;
  fail("no COLMAP model in " + folder + ": expected sparse/0/, sparse/ or the folder itself to hold cameras.bin or cameras.txt");
}

// Camera intrinsics and lens (engine/camera/lens.h), the pixel units divided by the image
// folder's factor (the lens's coefficients act on normalised points, so they stay).
void intrinsics(const ColmapCamera& c, int factor, Camera& out, const std::string& where) {
  const std::string camera = where + ": camera " + std::to_string(c.id);
  LensIntrinsics in = intrinsicsFromColmap(c.model, c.params, camera);
  if (!(in.fx > 0 && in.fy > 0)) fail(camera + " has a focal length <= 0");
  out.fx = in.fx / factor, out.fy = in.fy / factor, out.cx = in.cx / factor, out.cy = in.cy / factor;
  out.lens = in.lens;
  out.width = int(std::lround(double(c.width) / factor));
  out.height = int(std::lround(double(c.height) / factor));
  checkLensCoversImage(out, camera + " (" + c.model + ")");
}

// Camera-to-world in COLMAP's frame, Blender axes (right, up, back): the world-to-camera
// [R | t] inverted, then the OpenCV camera's y (down) and z (forward) negated.
glm::dmat4 cameraToWorld(const ColmapImage& im) {
  glm::dmat3 r = colmapRotation(im.q);
  glm::dmat3 rt = glm::transpose(r);
  glm::dvec3 centre = -(rt * im.t);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(rt[0], 0);
  m[1] = glm::dvec4(-rt[1], 0);
  m[2] = glm::dvec4(-rt[2], 0);
  m[3] = glm::dvec4(centre, 1);
  return m;
}

// The model's images that are on disk (sorted by name); the missing and the unregistered files
// counted in d.notes, not dropped silently.
std::vector<ColmapImage> presentImages(ColmapModel& m, const std::string& imageDir, Dataset& d) {
  std::sort(m.images.begin(), m.images.end(), [](const ColmapImage& a, const ColmapImage& b) { return a.name < b.name; });
  std::set<std::string> registered;
  std::vector<ColmapImage> present;
  size_t missing = 0;
  for (const ColmapImage& im : m.images) {
    registered.insert(im.name);
    registered.insert(replaceExtension(im.name, "_mask.png"));  // its mask beside it is no unregistered image
    if (fileExists(imageDir + "/" + im.name)) present.push_back(im);
    else missing++;
  }
  size_t unregistered = 0;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(imageDir, ec))
    if (e.is_regular_file() && !registered.count(fs::relative(e.path(), imageDir).generic_string())) unregistered++;
  if (missing) d.notes.push_back(std::to_string(missing) + " of the model's " + std::to_string(m.images.size()) + " images are not in " + imageDir + ": left out");
  if (unregistered) d.notes.push_back(std::to_string(unregistered) + " files in " + imageDir + " are not registered in the model: left out");
  return present;
}

// One registered image as a view in the water's frame, with its image and mask.
View colmapView(const std::string& folder, const std::string& model, const ColmapModel& m, const ColmapImage& im, const glm::dmat4& pose,
                const WaterFrame& f, const Dataset& d, const DatasetOptions& options) {
  const int factor = options.llffFactor;
  const std::string imageDir = imageFolder(folder, factor);
  const std::string where = model + ": image " + std::to_string(im.id) + " (" + im.name + ")";
  View v;
  v.name = fs::path(imageDir).filename().string() + "/" + im.name;
  intrinsics(m.cameras.at(im.cameraId), factor, v.camera, where);
  v.camera.cameraToWorld = poseInWaterFrame(pose, f, d);
  validateCameraToWorld(v.camera.cameraToWorld, where);
  v.image = loadViewImage(imageDir + "/" + im.name, 0, 0, options.background, where);
  // images_<N> scaled by 1/N, rounded either way
  if (std::abs(v.image.width - v.camera.width) > 1 || std::abs(v.image.height - v.camera.height) > 1)
    fail(where + ": the image is " + std::to_string(v.image.width) + " x " + std::to_string(v.image.height) + ", the camera " +
         std::to_string(v.camera.width) + " x " + std::to_string(v.camera.height) + (factor > 1 ? " (its size / " + std::to_string(factor) + ")" : ""));
  v.camera.width = v.image.width, v.camera.height = v.image.height;
  v.mask = loadViewMask(imageDir + "/" + im.name, maskFolder(folder, factor) + "/" + replaceExtension(im.name, ".png"), v.image.width,
                        v.image.height, where);
  return v;
}

}  // namespace

Dataset loadColmapDataset(const std::string& folder, const DatasetOptions& options) {
  const std::string model = modelFolder(folder);
  ColmapModel m = readColmapModel(model);
  if (m.images.empty()) fail("COLMAP model " + model + " has no registered images");
  const std::string imageDir = imageFolder(folder, options.llffFactor);
  if (!fs::is_directory(imageDir)) fail("COLMAP dataset " + folder + ": no image folder " + imageDir);
  Dataset d;
  d.root = folder;
  d.format = "colmap";
  const std::vector<ColmapImage> present = presentImages(m, imageDir, d);
  if (present.size() < 2) fail("COLMAP dataset " + folder + ": " + std::to_string(present.size()) + " registered images found in " + imageDir + " (at least 2 needed)");
  std::vector<std::string> presentNames;
  for (const ColmapImage& im : present) presentNames.push_back(im.name);
  const std::vector<bool> test = testViewFlags(presentNames, options, "COLMAP dataset " + folder);

  std::vector<glm::dmat4> poses;
  for (const ColmapImage& im : present) poses.push_back(cameraToWorld(im));
  std::vector<glm::dvec3> points;
  for (const ColmapPoint& p : m.points) points.push_back(p.position);
  const WaterFrame frame = deriveWaterFrame(points, poses, options, "COLMAP's frame", d);
  d.water = waterInFrame(folder, options, frame, "COLMAP dataset " + folder, d);
  for (const ColmapPoint& p : m.points) d.points.push_back({glm::dvec3(d.normalization * glm::dvec4(p.position, 1)), p.colour});
  for (size_t i = 0; i < present.size(); i++)
    d.splits[test[i] ? "test" : "train"].push_back(colmapView(folder, model, m, present[i], poses[i], frame, d, options));
  noteMasks(d);
  return d;
}

}  // namespace refrax
