#pragma once
// A camera as the datasets give it (Blender/NeRF convention): camera-to-world with columns
// right, up, back (the camera looks down its -Z) and position; focal lengths and principal
// point in pixels, pixel centres at integer + 0.5 (shaders/include/camera_direction.glsl);
// a lens (engine/camera/lens.h), a pinhole unless the dataset says otherwise.
#include <glm/glm.hpp>

#include "engine/camera/lens.h"

namespace refrax {

struct Camera {
  glm::dmat4 cameraToWorld{1.0};
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  Lens lens;

  glm::dvec3 position() const { return glm::dvec3(cameraToWorld[3]); }
  glm::dvec3 right() const { return glm::dvec3(cameraToWorld[0]); }
  glm::dvec3 up() const { return glm::dvec3(cameraToWorld[1]); }
  glm::dvec3 back() const { return glm::dvec3(cameraToWorld[2]); }

  // Unit world direction of the ray through continuous image point (u, v) in pixels (pixel
  // corners at integers), through the lens; in double precision (the reference's ray).
  glm::dvec3 rayDirection(double u, double v) const;
  // The image point (u, v) in pixels where the straight ray from the camera to world point p
  // meets the image (the inverse of rayDirection); false when p is behind a perspective lens.
  bool project(const glm::dvec3& p, glm::dvec2& uv) const;
  // Whether the straight ray from the camera to world point p passes through the image.
  bool sees(const glm::dvec3& p) const {
    glm::dvec2 uv;
    return project(p, uv) && uv.x >= 0 && uv.x <= width && uv.y >= 0 && uv.y <= height;
  }
};

// The camera whose pixel (x, y) is the block of factor x factor pixels at (factor x, factor y)
// (the remainder columns and rows cropped): the focal lengths and principal point divided by
// the factor, the lens unchanged (its terms act on normalised coordinates).
Camera downscaledCamera(const Camera& camera, int factor);

}  // namespace refrax
