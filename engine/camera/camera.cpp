#include "engine/camera/camera.h"

#include <algorithm>
#include <cmath>

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
  Camera c = camera;
  const double f = double(std::max(factor, 1));
  c.fx /= f;
  c.fy /= f;
  c.cx /= f;
  c.cy /= f;
  c.width = camera.width / std::max(factor, 1);
  c.height = camera.height / std::max(factor, 1);
  return c;
}

}  // namespace refrax
