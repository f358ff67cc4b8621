#include "engine/dataset/pose_alignment.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/dataset/symmetric_eigen.h"

namespace refrax {
namespace {

glm::dvec3 mean(const std::vector<glm::dvec3>& v) {
  glm::dvec3 m(0.0);
  for (const auto& p : v) m += p;
  return m / double(v.size());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

glm::dvec3 applySimilarity(const Similarity& s, const glm::dvec3& p) { return s.scale * (s.rotation * p) + s.translation; }

glm::dmat4 applySimilarity(const Similarity& s, const glm::dmat4& c2w) {
  glm::dmat4 m(1.0);
  for (int c = 0; c < 3; c++) m[c] = glm::dvec4(s.rotation * glm::dvec3(c2w[c]), 0);
  m[3] = glm::dvec4(applySimilarity(s, glm::dvec3(c2w[3])), 1);
  return m;
}

Similarity fitSimilarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to) {
  if (from.size() != to.size())
    fail("pose alignment: " + std::to_string(from.size()) + " estimated and " + std::to_string(to.size()) + " true camera centres");
  if (from.size() < 3) fail("pose alignment: " + std::to_string(from.size()) + " matched cameras (at least 3 needed)");
  const glm::dvec3 mf = mean(from), mt = mean(to);
  // Cross-covariance S[a][b] = sum x_a y_b of the centred points, and the spread of `from`.
  double s[3][3] = {}, cov[4][4] = {};
  double spread = 0;
  for (size_t i = 0; i < from.size(); i++) {
    glm::dvec3 x = from[i] - mf, y = to[i] - mt;
    spread += glm::dot(x, x);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        s[a][b] += x[a] * y[b];
        cov[a][b] += x[a] * x[b];
      }
  }
  // Collinear (or coincident) centres leave the rotation about their line free: the second
  // largest principal spread must not vanish next to the largest.
  double spreadValues[4];
  const SymmetricEigen spreads = symmetricEigen(cov, 3);
  std::copy(spreads.values, spreads.values + 3, spreadValues);
  std::sort(spreadValues, spreadValues + 3);
  if (!(spreadValues[1] > 1e-10 * spreadValues[2]) || !(spread > 0))
    fail("pose alignment: the estimated camera centres are (nearly) collinear; a similarity cannot be fitted to them");

  // Horn (1987): the unit quaternion maximising sum y . R x is the eigenvector of the largest
  // eigenvalue of this symmetric 4 x 4 matrix.
  double n[4][4] = {
      {s[0][0] + s[1][1] + s[2][2], s[1][2] - s[2][1], s[2][0] - s[0][2], s[0][1] - s[1][0]},
      {s[1][2] - s[2][1], s[0][0] - s[1][1] - s[2][2], s[0][1] + s[1][0], s[2][0] + s[0][2]},
      {s[2][0] - s[0][2], s[0][1] + s[1][0], -s[0][0] + s[1][1] - s[2][2], s[1][2] + s[2][1]},
      {s[0][1] - s[1][0], s[2][0] + s[0][2], s[1][2] + s[2][1], -s[0][0] - s[1][1] + s[2][2]},
  };
  const SymmetricEigen horn = symmetricEigen(n, 4);
  const int best = horn.largest();
  glm::dvec4 q(horn.vectors[0][best], horn.vectors[1][best], horn.vectors[2][best], horn.vectors[3][best]);  // (w, x, y, z)
  Similarity out;
  out.rotation = colmapRotation(q / glm::length(q));  // the standard quaternion-to-matrix map
  // The least-squares scale for that rotation: sum y . R x / sum |x|^2.
  double dot = 0;
  for (size_t i = 0; i < from.size(); i++) dot += glm::dot(to[i] - mt, out.rotation * (from[i] - mf));
  out.scale = dot / spread;
  out.translation = mt - out.scale * (out.rotation * mf);
  return out;
}

double rotationAngleDeg(const glm::dmat3& a, const glm::dmat3& b) {
  glm::dmat3 r = glm::transpose(a) * b;
  // atan2 of the axis part's length and the cosine keeps small angles accurate (acos does not).
  double c = 0.5 * (r[0][0] + r[1][1] + r[2][2] - 1);
  glm::dvec3 axis(r[1][2] - r[2][1], r[2][0] - r[0][2], r[0][1] - r[1][0]);
  return std::atan2(0.5 * glm::length(axis), c) * 180.0 / 3.14159265358979323846;
}

PoseErrors poseErrors(const std::vector<glm::dmat4>& aligned, const std::vector<glm::dmat4>& truth) {
  if (aligned.size() != truth.size()) fail("pose errors: " + std::to_string(aligned.size()) + " aligned and " + std::to_string(truth.size()) + " true cameras");
  if (aligned.empty()) fail("pose errors: no cameras");
  PoseErrors e;
  for (size_t i = 0; i < aligned.size(); i++) {
    e.rotationDeg.push_back(rotationAngleDeg(glm::dmat3(aligned[i]), glm::dmat3(truth[i])));
    e.centre.push_back(glm::length(glm::dvec3(aligned[i][3]) - glm::dvec3(truth[i][3])));
    for (size_t j = 0; j < i; j++) e.extent = std::max(e.extent, glm::length(glm::dvec3(truth[i][3]) - glm::dvec3(truth[j][3])));
  }
  e.rotationMedianDeg = median(e.rotationDeg);
  e.rotationMaxDeg = *std::max_element(e.rotationDeg.begin(), e.rotationDeg.end());
  e.centreMedian = median(e.centre);
  e.centreMax = *std::max_element(e.centre.begin(), e.centre.end());
  return e;
}

}  // namespace refrax
