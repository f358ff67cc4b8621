#include "engine/camera_rays.h"

#include <glm/glm.hpp>

#include "engine/error.h"

namespace refrax {

PinholeCamera lookAtCamera(const float eye[3], const float target[3], float tanHalfX, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0) fail("camera with an empty image");
  glm::vec3 e(eye[0], eye[1], eye[2]), t(target[0], target[1], target[2]);
  glm::vec3 f = t - e;
  if (glm::length(f) == 0.0f) fail("camera looks at its own position");
  f = glm::normalize(f);
  glm::vec3 side = glm::cross(f, glm::vec3(0, 0, 1));
  if (glm::length(side) < 1e-6f) side = glm::cross(f, glm::vec3(0, 1, 0));  // looking straight up or down
  glm::vec3 r = glm::normalize(side), u = glm::cross(r, f);
  r *= tanHalfX;
  u *= tanHalfX * float(height) / float(width);
  PinholeCamera c{};
  for (int a = 0; a < 3; a++) {
    c.position[a] = e[a];
    c.forward[a] = f[a];
    c.right[a] = r[a];
    c.up[a] = u[a];
  }
  return c;
}

std::vector<GpuRay> cameraRays(const PinholeCamera& c, uint32_t width, uint32_t height, float tmin, float tmax) {
  std::vector<GpuRay> rays(size_t(width) * height);
  glm::vec3 f(c.forward[0], c.forward[1], c.forward[2]), r(c.right[0], c.right[1], c.right[2]), u(c.up[0], c.up[1], c.up[2]);
  for (uint32_t py = 0; py < height; py++)
    for (uint32_t px = 0; px < width; px++) {
      float ux = (float(px) + 0.5f) / float(width) * 2.0f - 1.0f, uy = (float(py) + 0.5f) / float(height) * 2.0f - 1.0f;
      glm::vec3 d = glm::normalize(f + ux * r - uy * u);
      GpuRay& ray = rays[size_t(py) * width + px];
      for (int a = 0; a < 3; a++) {
        ray.origin[a] = c.position[a];
        ray.dir[a] = d[a];
      }
      ray.tmin = tmin;
      ray.tmax = tmax;
    }
  return rays;
}

}  // namespace refrax
