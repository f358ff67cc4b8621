#pragma once
// A pinhole camera as the datasets give it (Blender/NeRF convention): camera-to-world with
// columns right, up, back (the camera looks down its -Z) and position; focal lengths and
// principal point in pixels, pixel centres at integer + 0.5 (shaders/include/pinhole.glsl).
#include <glm/glm.hpp>

namespace refrax {

struct Camera {
  glm::dmat4 cameraToWorld{1.0};
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  glm::dvec3 position() const { return glm::dvec3(cameraToWorld[3]); }
  glm::dvec3 right() const { return glm::dvec3(cameraToWorld[0]); }
  glm::dvec3 up() const { return glm::dvec3(cameraToWorld[1]); }
  glm::dvec3 back() const { return glm::dvec3(cameraToWorld[2]); }

  // Whether the straight ray from the camera to world point p passes through the image (the
  // inverse of pinholeDirection: u = cx + fx x/depth, v = cy - fy y/depth, in front only).
  bool sees(const glm::dvec3& p) const {
    glm::dvec3 d = p - position();
    double depth = -glm::dot(d, back());
    if (!(depth > 0)) return false;
    double u = cx + fx * glm::dot(d, right()) / depth, v = cy - fy * glm::dot(d, up()) / depth;
    return u >= 0 && u <= width && v >= 0 && v <= height;
  }
};

}  // namespace refrax
