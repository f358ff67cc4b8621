// COLMAP dataset loader: a sparse model (engine/dataset/colmap_model.h) and its images, in a
// frame derived for the water (documented in engine/dataset/dataset.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/dataset/symmetric_eigen.h"
#include "engine/dataset/dataset.h"
#include "engine/dataset/view_image.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

std::string text(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.4g", v);
  return s;
}

std::string vectorText(const glm::dvec3& v) { return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ")"; }

// The model folder: sparse/0, sparse, or the dataset folder itself.
std::string modelFolder(const std::string& folder) {
  for (const std::string& f : {folder + "/sparse/0", folder + "/sparse", folder})
    if (hasColmapModel(f)) return f;
  fail("no COLMAP model in " + folder + ": expected sparse/0/, sparse/ or the folder itself to hold cameras.bin or cameras.txt");
}

// Camera intrinsics for a pinhole model, divided by the image folder's factor; other models
// are refused with the fix.
void intrinsics(const ColmapCamera& c, int factor, Camera& out, const std::string& where) {
  double fx, fy, cx, cy;
  if (c.model == "PINHOLE") {
    fx = c.params[0], fy = c.params[1], cx = c.params[2], cy = c.params[3];
  } else if (c.model == "SIMPLE_PINHOLE") {
    fx = fy = c.params[0], cx = c.params[1], cy = c.params[2];
  } else {
    fail(where + ": camera " + std::to_string(c.id) + " uses COLMAP's " + c.model +
         " model (lens distortion), which Refrax does not undistort: run `colmap image_undistorter` on the model and point "
         "Refrax at its output (PINHOLE cameras and undistorted images)");
  }
  if (!(fx > 0 && fy > 0)) fail(where + ": camera " + std::to_string(c.id) + " has a focal length <= 0");
  out.fx = fx / factor, out.fy = fy / factor, out.cx = cx / factor, out.cy = cy / factor;
  out.width = int(std::lround(double(c.width) / factor));
  out.height = int(std::lround(double(c.height) / factor));
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

// Smallest-eigenvalue eigenvector of a symmetric 3x3 matrix (the normal of a plane fit).
glm::dvec3 leastAxis(const glm::dmat3& a) {
  double m[4][4] = {};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) m[i][j] = a[j][i];
  const SymmetricEigen e = symmetricEigen(m, 3);
  const int k = e.smallest();
  return glm::dvec3(e.vectors[0][k], e.vectors[1][k], e.vectors[2][k]);
}

// "Up" for the water (toward the cameras): given, or derived from the cameras (see dataset.h).
glm::dvec3 deriveUp(const std::vector<glm::dmat4>& poses, const DatasetOptions& options, std::string& how) {
  if (options.up) {
    how = "given (--up)";
    return glm::normalize(*options.up);
  }
  glm::dvec3 forward(0), centre(0);
  for (const auto& m : poses) {
    forward += -glm::dvec3(m[2]);
    centre += glm::dvec3(m[3]);
  }
  centre /= double(poses.size());
  const double agreement = glm::length(forward) / double(poses.size());  // 1: all look the same way
  if (agreement > 0.5 || poses.size() < 3) {
    how = "opposite the cameras' mean viewing direction (they agree to " + text(agreement) + ")";
    return -glm::normalize(forward);
  }
  glm::dmat3 cov(0.0);
  for (const auto& m : poses) {
    glm::dvec3 d = glm::dvec3(m[3]) - centre;
    cov += glm::outerProduct(d, d);
  }
  glm::dvec3 n = leastAxis(cov);
  if (glm::dot(n, forward) > 0) n = -n;  // toward the cameras: against where they look
  how = "the normal of the plane of the camera centres, toward the cameras (their viewing directions agree to only " + text(agreement) + ")";
  return n;
}

// A rotation taking unit `up` to +Z (the shortest one).
glm::dmat3 rotationToZ(const glm::dvec3& up) {
  glm::dvec3 z(0, 0, 1);
  double c = glm::dot(up, z);
  glm::dvec3 axis = glm::cross(up, z);
  double s = glm::length(axis);
  if (s < 1e-12) return c > 0 ? glm::dmat3(1.0) : glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
  axis /= s;
  glm::dmat3 k(glm::dvec3(0, axis.z, -axis.y), glm::dvec3(-axis.z, 0, axis.x), glm::dvec3(axis.y, -axis.x, 0));
  return glm::dmat3(1.0) + s * k + (1 - c) * (k * k);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[size_t(std::lround(q * double(v.size() - 1)))];
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

// The water's frame: up to +Z, the mean camera over the origin, one unit the cameras' median
// height above the sparse points (the scene). Sets d.normalization; returns the sparse points'
// heights in that frame before scaling, and the rotation and scale.
struct ColmapFrame {
  glm::dmat3 rot{1.0};
  double scale = 1;
  std::vector<double> pointZ;
};
ColmapFrame waterFrame(const ColmapModel& m, const std::vector<glm::dmat4>& poses, const DatasetOptions& options, Dataset& d) {
  ColmapFrame f;
  std::string upHow;
  const glm::dvec3 up = deriveUp(poses, options, upHow);
  f.rot = rotationToZ(up);
  glm::dvec3 centre(0);
  for (const auto& p : poses) centre += f.rot * glm::dvec3(p[3]);
  centre /= double(poses.size());
  std::string scaleHow = "COLMAP's units (no sparse points to scale by)";
  for (const ColmapPoint& p : m.points) f.pointZ.push_back((f.rot * p.position).z - centre.z);
  if (f.pointZ.size() >= 10) {
    double depth = -quantile(f.pointZ, 0.5);
    if (depth > 0) {
      f.scale = 1 / depth;
      scaleHow = "1 = the median depth of the sparse points under the cameras";
    }
  }
  glm::dmat4 normalization(1.0);
  for (int c = 0; c < 3; c++) normalization[c] = glm::dvec4(f.scale * f.rot[c], 0);
  normalization[3] = glm::dvec4(-f.scale * centre, 1);
  d.normalization = normalization;
  d.notes.push_back("frame: up " + vectorText(up) + " in COLMAP's frame, " + upHow + "; mean camera at the origin; scale " + text(f.scale) +
                    " (" + scaleHow + ")");
  return f;
}

// The water height from the options or water.json, else estimated from the sparse points.
WaterMetadata colmapWater(const std::string& folder, const DatasetOptions& options, const ColmapFrame& f, Dataset& d) {
  WaterMetadata water = loadWaterMetadata(folder, options);
  if (water.height) return water;
  if (f.pointZ.size() < 10)
    fail("COLMAP dataset " + folder + ": the water height cannot be estimated from " + std::to_string(f.pointZ.size()) +
         " sparse points: give --water-height (in the frame `refrax inspect` prints) or water.json's \"height\"");
  // The dry rim around the water (a pool's edge, a tank's rim) is at or above the water and
  // is what COLMAP matches best; points seen through the water sit lower. So: a high
  // quantile of the points' heights, which `refrax inspect` prints to be checked.
  water.height = quantile(f.pointZ, 0.95) * f.scale;
  d.notes.push_back("water height " + text(*water.height) + " estimated: the 95th percentile of the sparse points' heights (the dry "
                    "rim); give --water-height to override");
  return water;
}

// One registered image as a view in the water's frame, with its image and mask.
View colmapView(const std::string& folder, const std::string& model, const ColmapModel& m, const ColmapImage& im, const glm::dmat4& pose,
                const ColmapFrame& f, const Dataset& d, const DatasetOptions& options) {
  const int factor = options.llffFactor;
  const std::string imageDir = imageFolder(folder, factor);
  const std::string where = model + ": image " + std::to_string(im.id) + " (" + im.name + ")";
  View v;
  v.name = fs::path(imageDir).filename().string() + "/" + im.name;
  intrinsics(m.cameras.at(im.cameraId), factor, v.camera, where);
  // the rotation turns the camera's axes; the scale moves only its position
  glm::dmat4 c2w(1.0);
  for (int c = 0; c < 3; c++) c2w[c] = glm::dvec4(f.rot * glm::dvec3(pose[c]), 0);
  c2w[3] = d.normalization * pose[3];
  v.camera.cameraToWorld = c2w;
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
  const ColmapFrame frame = waterFrame(m, poses, options, d);
  d.water = colmapWater(folder, options, frame, d);
  for (const ColmapPoint& p : m.points) d.points.push_back({glm::dvec3(d.normalization * glm::dvec4(p.position, 1)), p.colour});
  for (size_t i = 0; i < present.size(); i++)
    d.splits[test[i] ? "test" : "train"].push_back(colmapView(folder, model, m, present[i], poses[i], frame, d, options));
  noteMasks(d);
  return d;
}

}  // namespace refrax
