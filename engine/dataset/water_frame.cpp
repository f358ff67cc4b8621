#include "engine/dataset/water_frame.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/base/number_text.h"
#include "engine/dataset/symmetric_eigen.h"

namespace refrax {
namespace {

std::string text(double v) { return numberText(v, 4); }

std::string vectorText(const glm::dvec3& v) { return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ")"; }

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

}  // namespace

WaterFrame deriveWaterFrame(const std::vector<glm::dvec3>& points, const std::vector<glm::dmat4>& poses, const DatasetOptions& options,
                            const std::string& source, Dataset& d) {
  WaterFrame f;
  std::string upHow;
  const glm::dvec3 up = deriveUp(poses, options, upHow);
  f.rotation = rotationToZ(up);
  glm::dvec3 centre(0);
  for (const auto& p : poses) centre += f.rotation * glm::dvec3(p[3]);
  centre /= double(poses.size());
  std::string scaleHow = "the source's units (fewer than 10 sparse points to scale by)";
  for (const glm::dvec3& p : points) f.pointHeights.push_back((f.rotation * p).z - centre.z);
  if (f.pointHeights.size() >= 10) {
    double depth = -quantile(f.pointHeights, 0.5);
    if (depth > 0) {
      f.scale = 1 / depth;
      scaleHow = "1 = the median depth of the sparse points under the cameras";
    }
  }
  glm::dmat4 normalization(1.0);
  for (int c = 0; c < 3; c++) normalization[c] = glm::dvec4(f.scale * f.rotation[c], 0);
  normalization[3] = glm::dvec4(-f.scale * centre, 1);
  d.normalization = normalization;
  d.notes.push_back("frame: up " + vectorText(up) + " in " + source + ", " + upHow + "; mean camera at the origin; scale " + text(f.scale) +
                    " (" + scaleHow + ")");
  return f;
}

glm::dmat4 poseInWaterFrame(const glm::dmat4& pose, const WaterFrame& f, const Dataset& d) {
  glm::dmat4 c2w(1.0);
  for (int c = 0; c < 3; c++) c2w[c] = glm::dvec4(f.rotation * glm::dvec3(pose[c]), 0);
  c2w[3] = d.normalization * pose[3];
  return c2w;
}

WaterMetadata waterInFrame(const std::string& folder, const DatasetOptions& options, const WaterFrame& f, const std::string& what, Dataset& d) {
  WaterMetadata water = loadWaterMetadata(folder, options);
  if (water.height) return water;
  if (f.pointHeights.size() < 10)
    fail(what + ": the water height cannot be estimated from " + std::to_string(f.pointHeights.size()) +
         " sparse points: give --water-height (in the frame `refrax inspect` prints) or water.json's \"height\"");
  // The dry rim around the water (a pool's edge, a tank's rim) is at or above the water and
  // is what COLMAP matches best; points seen through the water sit lower. So: a high
  // quantile of the points' heights, which `refrax inspect` prints to be checked.
  water.height = quantile(f.pointHeights, 0.95) * f.scale;
  d.notes.push_back("water height " + text(*water.height) + " estimated: the 95th percentile of the sparse points' heights (the dry "
                    "rim); give --water-height to override");
  return water;
}

}  // namespace refrax
