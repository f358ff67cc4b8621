#include "engine/camera/camera.h"

#include <cmath>

#include "engine/camera/lens_math.h"

namespace refrax {

glm::dvec3 Camera::rayDirection(double u, double v) const {
  return f64::cameraDirection(right(), up(), back(), glm::dvec4(fx, fy, cx, cy), int(lens.kind), lens.radial, lens.extra, glm::dvec2(u, v));
}

bool Camera::project(const glm::dvec3& p, glm::dvec2& uv) const {
  const glm::dvec3 d = p - position();
  const glm::dvec3 local(glm::dot(d, right()), -glm::dot(d, up()), -glm::dot(d, back()));  // OpenCV's frame, z forward
  glm::dvec2 m;
  if (lens.kind == LensKind::Fisheye) {
    if (!(glm::length(local) > 0)) return false;
    m = f64::lensProject(LENS_FISHEYE, lens.radial, lens.extra, local);
    // Past the lens's largest angle its polynomial may turn back into the image: only the
    // rising branch images a point.
    double slope = 0, theta = std::atan2(glm::length(glm::dvec2(local)), local.z);
    const double thetaD = f64::lensFisheyeRadius(lens.radial, theta, slope);
    if (!(slope > 0) || (theta > 0 && !(thetaD > 0))) return false;
  } else {
    if (!(local.z > 0)) return false;
    const glm::dvec2 q = glm::dvec2(local) / local.z;
    m = q;
    if (lens.kind == LensKind::RadialTangential) {
      // Likewise a distortion that folds over far outside the image maps such points back into it.
      glm::dvec2 dx, dy;
      m = f64::lensRadialTangential(lens.radial, lens.extra, q, dx, dy);
      if (!(dx.x * dy.y - dy.x * dx.y > 0) || glm::dot(m, q) < 0) return false;
    }
  }
  uv = glm::dvec2(cx + fx * m.x, cy + fy * m.y);
  return std::isfinite(uv.x) && std::isfinite(uv.y);
}

}  // namespace refrax
