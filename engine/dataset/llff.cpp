// LLFF dataset loader with NeRF's load_llff.py conventions (documented in engine/dataset/dataset.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/dataset/dataset.h"
#include "engine/dataset/view_image.h"
#include "engine/base/error.h"
#include "engine/base/number_text.h"
#include "engine/io/atomic_file.h"
#include "engine/io/npy.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

glm::dvec3 normalized(const glm::dvec3& v) { return v / glm::length(v); }

// A value of the file as the message shows it (%g: any double, not only those an int holds).
std::string number(double v) { return numberText(v); }

std::vector<std::string> imageFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string ext = entry.path().extension().string();
    const std::string name = entry.path().filename().string();
    const bool mask = name.size() > 9 && name.compare(name.size() - 9, 9, "_mask.png") == 0;  // a mask beside its image
    if (entry.is_regular_file() && !mask && (ext == ".png" || ext == ".PNG" || ext == ".jpg" || ext == ".JPG" || ext == ".jpeg"))
      files.push_back(name);
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Every camera at one point (poses written as integers, or copied rows) cannot be trained on.
void requireDistinctCameras(const std::vector<Camera>& cameras, const std::string& where) {
  if (cameras.size() < 2) return;
  glm::dvec3 first = cameras[0].position();
  for (const Camera& c : cameras)
    if (glm::length(c.position() - first) > 1e-9) return;
  fail(where + ": every camera is at the same point (" + std::to_string(first.x) + ", " + std::to_string(first.y) + ", " +
       std::to_string(first.z) + "); the poses cannot be told apart");
}

}  // namespace

LlffCameras llffCameras(const std::vector<double>& pb, size_t count, int factor, int imageWidth, int imageHeight, const std::string& where,
                        bool keepFrame) {
  if (pb.size() != count * 17) fail(where + ": expected " + std::to_string(count) + " rows of 17 values");
  if (factor < 1) fail(where + ": the image factor must be at least 1");
  LlffCameras out;
  std::vector<glm::dmat4> poses(count);
  double minNear = INFINITY;
  for (size_t i = 0; i < count; i++) {
    const double* row = &pb[i * 17];
    const std::string at = where + ": pose " + std::to_string(i);
    for (int k = 0; k < 17; k++)
      if (!std::isfinite(row[k])) fail(at + " has a non-finite value");
    // row-major 3x5: element (r, c) at row[5 r + c]; columns down, right, back, t, hwf
    auto col = [&](int c) { return glm::dvec3(row[c], row[5 + c], row[10 + c]); };
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(col(1), 0);   // right
    m[1] = glm::dvec4(-col(0), 0);  // up = -down
    m[2] = glm::dvec4(col(2), 0);   // back
    m[3] = glm::dvec4(col(3), 1);
    validateCameraToWorld(m, at);
    double h = row[4], w = row[9], focal = row[14];
    if (!(focal > 0)) fail(at + ": the focal length is not positive");
    // images_<factor> must be the full-resolution images scaled by 1/factor (rounded)
    if (std::abs(imageWidth - w / factor) >= 1.0 || std::abs(imageHeight - h / factor) >= 1.0)
      fail(at + ": images are " + std::to_string(imageWidth) + "x" + std::to_string(imageHeight) + ", the poses say " +
           number(w) + "x" + number(h) + " / " + std::to_string(factor));
    double nearB = row[15], farB = row[16];
    if (!(nearB > 0) || !(farB >= nearB)) fail(at + ": bounds must satisfy 0 < near <= far");
    minNear = std::min(minNear, nearB);
    poses[i] = m;
    Camera c;
    c.width = imageWidth;
    c.height = imageHeight;
    c.fx = c.fy = focal / factor;
    c.cx = 0.5 * imageWidth;
    c.cy = 0.5 * imageHeight;
    out.cameras.push_back(c);
    out.nearBounds.push_back(nearB);
    out.farBounds.push_back(farB);
  }
  if (keepFrame) {
    for (size_t i = 0; i < count; i++) out.cameras[i].cameraToWorld = poses[i];
    requireDistinctCameras(out.cameras, where);
    return out;
  }
  // scale by the near bound (bd_factor 0.75)
  const double s = 1.0 / (0.75 * minNear);
  for (auto& m : poses) m[3] = glm::dvec4(glm::dvec3(m[3]) * s, 1.0);
  for (size_t i = 0; i < count; i++) {
    out.nearBounds[i] *= s;
    out.farBounds[i] *= s;
  }
  // recentre on the average pose
  glm::dvec3 centre(0), backSum(0), upSum(0);
  for (const auto& m : poses) {
    centre += glm::dvec3(m[3]);
    backSum += glm::dvec3(m[2]);
    upSum += glm::dvec3(m[1]);
  }
  centre /= double(count);
  glm::dvec3 back = normalized(backSum);
  glm::dvec3 right = normalized(glm::cross(upSum, back));
  glm::dvec3 up = normalized(glm::cross(back, right));
  glm::dmat4 average(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(back, 0), glm::dvec4(centre, 1));
  glm::dmat4 toCentred = glm::inverse(average);
  for (size_t i = 0; i < count; i++) out.cameras[i].cameraToWorld = toCentred * poses[i];
  requireDistinctCameras(out.cameras, where);
  glm::dmat4 scale(1.0);
  scale[0][0] = scale[1][1] = scale[2][2] = s;
  out.normalization = toCentred * scale;
  return out;
}

Dataset loadLlffDataset(const std::string& folder, const DatasetOptions& options) {
  const std::string npyPath = folder + "/poses_bounds.npy";
  NpyArray pb = readNpy(npyPath);
  if (pb.shape.size() != 2 || pb.shape[1] != 17) fail(npyPath + ": expected an N x 17 array");
  if (pb.integer) fail(npyPath + " holds integers: LLFF poses and bounds are float32 or float64 (integer rounding would move the cameras)");
  const size_t n = pb.shape[0];
  if (n == 0) fail(npyPath + ": no poses");
  const std::string imageDir = imageFolder(folder, options.llffFactor);
  if (!fs::is_directory(imageDir)) fail("LLFF dataset " + folder + ": no image folder " + imageDir);
  std::vector<std::string> files = imageFiles(imageDir);
  if (files.size() != n)
    fail(imageDir + " holds " + std::to_string(files.size()) + " images but " + npyPath + " has " + std::to_string(n) + " poses");
  const std::vector<bool> test = testViewFlags(files, options, "LLFF dataset " + folder);

  std::vector<Image> images;
  for (size_t i = 0; i < n; i++) {
    int w = images.empty() ? 0 : images[0].width, h = images.empty() ? 0 : images[0].height;
    images.push_back(loadViewImage(imageDir + "/" + files[i], w, h, options.background, npyPath + ": view " + std::to_string(i)));
  }
  WaterMetadata water = loadWaterMetadata(folder, options);  // its frame decides whether the poses are recentred
  LlffCameras cams = llffCameras(pb.data, n, options.llffFactor, images[0].width, images[0].height, npyPath, water.datasetFrame);

  Dataset d;
  d.root = folder;
  d.format = "llff";
  d.normalization = cams.normalization;
  for (size_t i = 0; i < n; i++) {
    View v;
    v.name = fs::path(imageDir).filename().string() + "/" + files[i];
    v.camera = cams.cameras[i];
    v.image = std::move(images[i]);
    v.nearBound = cams.nearBounds[i];
    v.farBound = cams.farBounds[i];
    v.mask = loadViewMask(imageDir + "/" + files[i], maskFolder(folder, options.llffFactor) + "/" + replaceExtension(files[i], ".png"),
                          v.image.width, v.image.height, npyPath + ": view " + std::to_string(i));
    d.splits[test[i] ? "test" : "train"].push_back(std::move(v));
  }
  d.water = water;
  noteMasks(d);
  return d;
}

}  // namespace refrax
