#pragma once
// How far a set of estimated camera poses (structure from motion's, in a frame of its own) is
// from the true ones: the similarity (rotation, translation, scale) that best maps the
// estimated camera centres onto the true ones in the least-squares sense (Umeyama's problem,
// solved with Horn's quaternion method), then each camera's rotation error (degrees) and
// centre error (the truth's units) once aligned. `refrax align-poses` reports these and writes
// the aligned poses as a dataset in the truth's frame.
#include <vector>

#include <glm/glm.hpp>

namespace refrax {

// to = scale * rotation * from + translation
struct Similarity {
  double scale = 1;
  glm::dmat3 rotation{1.0};
  glm::dvec3 translation{0.0};
};

glm::dvec3 applySimilarity(const Similarity& s, const glm::dvec3& p);
// A camera-to-world matrix moved by the similarity: its axes turned by the rotation (they
// stay unit length), its centre mapped.
glm::dmat4 applySimilarity(const Similarity& s, const glm::dmat4& cameraToWorld);

// The similarity minimising sum_i |scale R from_i + t - to_i|^2 with R a proper rotation.
// refrax::Error when the lists differ in length, hold fewer than 3 points, or the `from`
// points are (nearly) collinear: the rotation about their line would be undetermined.
Similarity fitSimilarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to);

// The angle (degrees) of the rotation taking a to b.
double rotationAngleDeg(const glm::dmat3& a, const glm::dmat3& b);

struct PoseErrors {
  std::vector<double> rotationDeg, centre;  // per camera
  double rotationMedianDeg = 0, rotationMaxDeg = 0;
  double centreMedian = 0, centreMax = 0;
  double extent = 0;  // the largest distance between two true camera centres
};

// Per-camera errors of cameras already in the truth's frame (camera-to-world, same order).
// refrax::Error when the lists differ in length or are empty.
PoseErrors poseErrors(const std::vector<glm::dmat4>& aligned, const std::vector<glm::dmat4>& truth);

}  // namespace refrax
