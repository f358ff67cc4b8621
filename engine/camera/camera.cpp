#include "engine/camera/camera.h"

#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/camera/lens_math.h"

namespace refrax {

glm::dvec3 Camera::rayDirection(double u, double v) const {
  return f64::cameraDirection(right(), up(), back(), glm::dvec4(fx, fy, cx, cy), int(lens.kind), lens.radial, lens.extra, glm::dvec2(u, v));
}

bool Camera::project(const glm::dvec3& p, glm::dvec2& uv) const {
  const glm::dvec3 d = p - position();
  const glm::dvec3 local(glm::dot(d, right()), -glm::dot(d, up()), -glm::dot(d, back()));  // OpenCV's frame, z forward
  if (!lensImagesDirection(lens, local)) return false;
  const glm::dvec2 m = f64::lensProject(int(lens.kind), lens.radial, lens.extra, local);
  uv = glm::dvec2(cx + fx * m.x, cy + fy * m.y);
  return std::isfinite(uv.x) && std::isfinite(uv.y);
}

Camera downscaledCamera(const Camera& camera, int factor) {
  if (factor < 1) fail("downscaledCamera: a factor of " + std::to_string(factor));
  Camera c = camera;
  c.fx /= factor;
  c.fy /= factor;
  c.cx /= factor;
  c.cy /= factor;
  c.width = camera.width / factor;
  c.height = camera.height / factor;
  return c;
}

}  // namespace refrax
