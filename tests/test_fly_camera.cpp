// Fly camera math: basis orthonormal, lookAt looks at the target, orbit keeps the distance.
#include <doctest/doctest.h>

#include <random>

#include "engine/view/fly_camera.h"
#include "tests/gpu_test.h"

using namespace refrax;

TEST_CASE("fly camera basis is orthonormal and lookAt points at the target") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<float> U(-3.0f, 3.0f);
  for (int i = 0; i < 200; i++) {
    FlyCamera cam;
    glm::vec3 p{U(rng), U(rng), 1.0f + std::abs(U(rng))}, t{U(rng), U(rng), -std::abs(U(rng))};
    lookAt(cam, p, t);
    CameraBasis b = cameraBasis(cam);
    CHECK(glm::length(b.forward) == doctest::Approx(1.0f).epsilon(1e-5));
    CHECK(glm::dot(b.forward, b.right) == doctest::Approx(0.0f).epsilon(1e-5));
    CHECK(glm::dot(b.forward, b.up) == doctest::Approx(0.0f).epsilon(1e-5));
    CHECK(b.up.z > 0.0f);  // Z is up: the image is not upside down
    CHECK(glm::dot(b.forward, glm::normalize(t - p)) == doctest::Approx(1.0f).epsilon(1e-4));
  }
}

TEST_CASE("fly moves along the view and orbit keeps the distance to the target") {
  FlyCamera cam;
  lookAt(cam, {0, -2, 0}, {0, 0, 0});
  flyMove(cam, 1.0f, 0.0f, 0.0f, 0.5f);  // speed 1, half a second forward
  CHECK(cam.position.y == doctest::Approx(-1.5f));
  cam.orbit = true;
  cam.orbitTarget = {0, 0, 0};
  float before = glm::length(cam.position);
  flyLook(cam, 0.7f, -0.3f);
  CHECK(glm::length(cam.position - cam.orbitTarget) == doctest::Approx(before).epsilon(1e-5));
  CHECK(glm::dot(cameraBasis(cam).forward, glm::normalize(cam.orbitTarget - cam.position)) == doctest::Approx(1.0f).epsilon(1e-4));
}
