// Camera rays on the device against the double reference, for whole images and pixel lists,
// and the pinhole convention itself on a case worked by hand.
#include <cmath>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "engine/camera/camera_rays.h"
#include "engine/reference/camera_rays_ref.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

Camera randomCamera(std::mt19937& rng, int width, int height) {
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  glm::dquat q = glm::normalize(glm::dquat(N(rng), N(rng), N(rng), N(rng)));
  Camera c;
  c.cameraToWorld = glm::dmat4(glm::mat3_cast(q));
  c.cameraToWorld[3] = glm::dvec4(N(rng) * 3, N(rng) * 3, 2 + U(rng), 1.0);
  c.width = width;
  c.height = height;
  c.fx = 20 + 40 * U(rng);
  c.fy = c.fx * (0.8 + 0.4 * U(rng));
  c.cx = width * (0.4 + 0.2 * U(rng));
  c.cy = height * (0.4 + 0.2 * U(rng));
  return c;
}

size_t countBadRays(const Camera& c, const std::vector<GpuRay>& rays, const std::vector<uint32_t>& pixels, float tmin, float tmax) {
  size_t bad = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    auto r = ref::cameraRay(c, int(pixels[i] % c.width), int(pixels[i] / c.width));
    double err = 0;
    for (int a = 0; a < 3; a++) {
      err = std::max(err, std::abs(rays[i].origin[a] - r.origin[a]) / (1 + std::abs(r.origin[a])));
      err = std::max(err, std::abs(rays[i].dir[a] - r.dir[a]));
    }
    if (!(err < 2e-6) || rays[i].tmin != tmin || rays[i].tmax != tmax) bad++;
  }
  return bad;
}

}  // namespace

TEST_CASE("pinhole convention: looks down -Z, image y downwards, through pixel centres") {
  Camera c;  // identity pose, 2x2 image, principal point at the image centre
  c.width = c.height = 2;
  c.fx = c.fy = 1;
  c.cx = c.cy = 1;
  auto topLeft = ref::cameraRay(c, 0, 0);
  glm::dvec3 expect = glm::normalize(glm::dvec3(-0.5, 0.5, -1.0));
  CHECK(glm::length(topLeft.dir - expect) < 1e-15);
  auto bottomRight = ref::cameraRay(c, 1, 1);
  CHECK(glm::length(bottomRight.dir - glm::normalize(glm::dvec3(0.5, -0.5, -1.0))) < 1e-15);
}

GPU_TEST_CASE("camera rays on the device match the double reference (every pixel and pixel lists)") {
  CameraRayPipelines pipes = createCameraRayPipelines(ctx);
  for (int trial = 0; trial < 3; trial++) {
    Camera c = randomCamera(rng, 37 + trial * 50, 23 + trial * 31);
    uint32_t n = uint32_t(c.width * c.height);
    Buffer rb = createBuffer(ctx, n * sizeof(GpuRay));
    fillBuffer(ctx, rb, 0x7FC00000u);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, pipes, c, rb, 0.0f, 50.0f); });
    std::vector<uint32_t> all(n);
    for (uint32_t i = 0; i < n; i++) all[i] = i;
    CHECK(countBadRays(c, downloadVector<GpuRay>(ctx, rb, n), all, 0.0f, 50.0f) == 0);

    std::uniform_int_distribution<uint32_t> P(0, n - 1);
    std::vector<uint32_t> list(501);
    for (auto& p : list) p = P(rng);
    Buffer lb = createBufferFrom(ctx, list);
    Buffer rl = createBuffer(ctx, (list.size() + 4) * sizeof(GpuRay));
    fillBuffer(ctx, rl, 0x7FC00000u);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdCameraRaysForPixels(cb, pipes, c, lb, uint32_t(list.size()), rl, 0.01f, 9.0f); });
    auto rays = downloadVector<GpuRay>(ctx, rl, list.size() + 4);
    CHECK(countBadRays(c, std::vector<GpuRay>(rays.begin(), rays.begin() + list.size()), list, 0.01f, 9.0f) == 0);
    CHECK(std::isnan(rays[list.size()].origin[0]));  // nothing written past the list
  }
  Camera broken;
  Buffer rb = createBuffer(ctx, 64);
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, pipes, broken, rb, 0.0f, 1.0f); }), Error);
}
