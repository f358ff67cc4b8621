// The viewer's camera conversions: a fly camera's pinhole camera equals the trainer's
// look-at camera, a dataset camera round-trips through the fly camera, resizing scales the
// intrinsics.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "engine/model/render_model.h"
#include "engine/view/view_camera.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {
double maxDiff(const glm::dmat4& a, const glm::dmat4& b) {
  double m = 0;
  for (int c = 0; c < 4; c++)
    for (int r = 0; r < 4; r++) m = std::max(m, std::abs(a[c][r] - b[c][r]));
  return m;
}
}  // namespace

TEST_CASE("the fly camera's pinhole camera is the look-at camera of render") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 50; i++) {
    glm::vec3 p(u(rng), u(rng), 1.0f + std::abs(u(rng))), t(u(rng) * 0.3f, u(rng) * 0.3f, -0.5f);
    if (std::abs(glm::normalize(t - p).z) > 0.99f) continue;  // the fly camera's pitch stops short of straight down
    FlyCamera fly;
    lookAt(fly, p, t);
    double fov = std::uniform_real_distribution<double>(0.3, 1.5)(rng);
    fly.tanHalfFovY = float(std::tan(fov / 2));
    Camera a = cameraFromFly(fly, 200, 150), b = lookAtCamera(glm::dvec3(p), glm::dvec3(t), 200, 150, fov);
    CHECK(maxDiff(a.cameraToWorld, b.cameraToWorld) < 2e-6);
    CHECK(std::abs(a.fy - b.fy) < 1e-4 * b.fy);
    CHECK(a.fx == a.fy);
    CHECK(a.cx == 100.0);
    CHECK(a.cy == 75.0);

    FlyCamera back = flyFromCamera(b, fly);
    Camera c = cameraFromFly(back, 200, 150);
    CHECK(maxDiff(c.cameraToWorld, b.cameraToWorld) < 2e-6);
    CHECK(std::abs(c.fy - b.fy) < 1e-4 * b.fy);
  }
}

TEST_CASE("a resized camera scales its intrinsics per axis and keeps its pose") {
  Camera c = lookAtCamera({0, -2, 1}, {0, 0, 0}, 400, 300, 0.8);
  c.cx = 210;
  c.fx = 350;
  Camera r = resizedCamera(c, 200, 100);
  CHECK(r.width == 200);
  CHECK(r.height == 100);
  CHECK(r.fx == doctest::Approx(175));
  CHECK(r.cx == doctest::Approx(105));
  CHECK(r.fy == doctest::Approx(c.fy / 3));
  CHECK(r.cy == doctest::Approx(50));
  CHECK(r.cameraToWorld == c.cameraToWorld);
  CHECK_THROWS_AS(resizedCamera(c, 0, 10), refrax::Error);
}
