#include "engine/camera_rays.h"

#include <glm/glm.hpp>

#include "engine/error.h"

namespace refrax {

std::vector<GpuRay> cameraRays(const GpuPinholeCamera& c, uint32_t width, uint32_t height, float tmin, float tmax) {
  if (width == 0 || height == 0) fail("camera rays for an empty image");
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
