// Pose alignment (engine/dataset/pose_alignment.h): a known similarity between two frames is
// recovered from cameras with noise on them, and the reported errors are the noise put in.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/base/error.h"
#include "engine/dataset/pose_alignment.h"

using namespace refrax;

namespace {

glm::dmat3 rotationAbout(const glm::dvec3& axis, double radians) { return glm::dmat3(glm::rotate(glm::dmat4(1.0), radians, glm::normalize(axis))); }

// A ring of cameras looking at the origin from 30 degrees up, with a second, higher ring: the
// layout structure from motion is given in scripts/colmap-check.sh.
std::vector<glm::dmat4> ringCameras() {
  std::vector<glm::dmat4> cams;
  for (double elevation : {0.52, 0.79})
    for (int i = 0; i < 12; i++) {
      double a = 2 * 3.14159265358979323846 * i / 12;
      glm::dvec3 eye = 2.0 * glm::dvec3(std::cos(elevation) * std::cos(a), std::cos(elevation) * std::sin(a), std::sin(elevation));
      glm::dvec3 back = glm::normalize(eye), right = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), back)), up = glm::cross(back, right);
      glm::dmat4 m(1.0);
      m[0] = glm::dvec4(right, 0);
      m[1] = glm::dvec4(up, 0);
      m[2] = glm::dvec4(back, 0);
      m[3] = glm::dvec4(eye, 1);
      cams.push_back(m);
    }
  return cams;
}

}  // namespace

TEST_CASE("pose alignment: a known similarity is recovered from noisy cameras, and the errors are the noise" * doctest::test_suite("one-backend")) {
  const std::vector<glm::dmat4> truth = ringCameras();
  // The estimate's frame: truth = known(estimate), so the estimate is the truth under the inverse.
  Similarity known;
  known.scale = 0.37;
  known.rotation = rotationAbout({0.3, -0.8, 0.5}, 2.3);
  known.translation = {1.5, -4.0, 0.7};
  Similarity inverse;
  inverse.scale = 1 / known.scale;
  inverse.rotation = glm::transpose(known.rotation);
  inverse.translation = -(inverse.scale * (inverse.rotation * known.translation));

  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const double centreNoise = 0.01, angleNoise = 0.5 * 3.14159265358979323846 / 180;  // truth units; radians
  std::vector<glm::dmat4> estimate;
  std::vector<double> turned;
  for (const glm::dmat4& t : truth) {
    glm::dmat4 noisy = t;
    glm::dvec3 axis(normal(rng), normal(rng), normal(rng));
    double angle = angleNoise * (0.5 + std::abs(normal(rng)));
    turned.push_back(angle * 180 / 3.14159265358979323846);
    glm::dmat3 r = rotationAbout(axis, angle) * glm::dmat3(t);
    for (int c = 0; c < 3; c++) noisy[c] = glm::dvec4(r[c], 0);
    noisy[3] = glm::dvec4(glm::dvec3(t[3]) + centreNoise * glm::dvec3(normal(rng), normal(rng), normal(rng)), 1);
    estimate.push_back(applySimilarity(inverse, noisy));
  }

  std::vector<glm::dvec3> from, to;
  for (size_t i = 0; i < truth.size(); i++) {
    from.push_back(glm::dvec3(estimate[i][3]));
    to.push_back(glm::dvec3(truth[i][3]));
  }
  const Similarity fit = fitSimilarity(from, to);
  CHECK(fit.scale == doctest::Approx(known.scale).epsilon(0.01));
  // The centre noise leaves the fitted rotation about 0.16 degrees off (0.01 / sqrt(sum of the
  // squared distances from each rotation axis): 0.075 about the vertical, 0.1 about each
  // horizontal axis); this seed's is 0.24.
  const double fitError = rotationAngleDeg(fit.rotation, known.rotation);
  CHECK(fitError < 0.4);
  CHECK(glm::length(fit.translation - known.translation) < 0.05);

  std::vector<glm::dmat4> aligned;
  for (const auto& e : estimate) aligned.push_back(applySimilarity(fit, e));
  const PoseErrors err = poseErrors(aligned, truth);
  REQUIRE(err.rotationDeg.size() == truth.size());
  // Each camera's rotation error is the turn put on it, give or take the fitted rotation's
  // error (the angles of two rotations differ by at most the angle between them).
  for (size_t i = 0; i < truth.size(); i++) CHECK(std::abs(err.rotationDeg[i] - turned[i]) <= fitError + 1e-9);
  // Centre noise 0.01 per axis: about 0.016 per camera, a few times that at most.
  CHECK(err.centreMedian > 0.005);
  CHECK(err.centreMedian < 0.03);
  CHECK(err.centreMax < 0.06);
  CHECK(err.extent == doctest::Approx(4 * std::cos(0.52)));  // opposite cameras of the lower ring
}

TEST_CASE("pose alignment: exact cameras align exactly, and a rotation's angle is measured" * doctest::test_suite("one-backend")) {
  const std::vector<glm::dmat4> truth = ringCameras();
  Similarity s;
  s.scale = 3.1;
  s.rotation = rotationAbout({-1, 0.2, 0.4}, -0.9);
  s.translation = {-2, 5, 1};
  std::vector<glm::dvec3> from, to;
  for (const auto& t : truth) {
    from.push_back(glm::dvec3(t[3]));
    to.push_back(applySimilarity(s, glm::dvec3(t[3])));
  }
  const Similarity fit = fitSimilarity(from, to);
  CHECK(fit.scale == doctest::Approx(s.scale).epsilon(1e-9));
  CHECK(rotationAngleDeg(fit.rotation, s.rotation) < 1e-6);
  CHECK(glm::length(fit.translation - s.translation) < 1e-9);
  CHECK(rotationAngleDeg(glm::dmat3(1.0), rotationAbout({0, 0, 1}, 0.5)) == doctest::Approx(0.5 * 180 / 3.14159265358979323846));
  CHECK(rotationAngleDeg(glm::dmat3(1.0), rotationAbout({1, 1, 0}, 3.0)) == doctest::Approx(3.0 * 180 / 3.14159265358979323846));
  CHECK(rotationAngleDeg(rotationAbout({0, 1, 0}, 1e-7), glm::dmat3(1.0)) == doctest::Approx(1e-7 * 180 / 3.14159265358979323846).epsilon(1e-6));
}

TEST_CASE("pose alignment: too few, collinear or unequal lists of centres are refused" * doctest::test_suite("one-backend")) {
  std::vector<glm::dvec3> two = {{0, 0, 0}, {1, 0, 0}}, line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  std::vector<glm::dvec3> four = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  CHECK_THROWS_WITH_AS(fitSimilarity(two, two), doctest::Contains("at least 3 needed"), Error);
  CHECK_THROWS_WITH_AS(fitSimilarity(line, line), doctest::Contains("collinear"), Error);
  CHECK_THROWS_WITH_AS(fitSimilarity(four, two), doctest::Contains("4 estimated and 2 true"), Error);
  CHECK_THROWS_WITH_AS(poseErrors({}, {}), doctest::Contains("no cameras"), Error);
}
