#pragma once
// CPU double reference of the camera rays (engine/camera/camera_rays.h).
#include "engine/camera/camera.h"
#include "engine/base/shared_math.h"

namespace refrax::f64 {
#include "pinhole.glsl"
}

namespace refrax::ref {

struct CameraRay {
  glm::dvec3 origin, dir;
};

// The ray through the centre of pixel (x, y).
inline CameraRay cameraRay(const Camera& c, int x, int y) {
  glm::dvec4 intrinsics(c.fx, c.fy, c.cx, c.cy);
  return {c.position(), f64::pinholeDirection(c.right(), c.up(), c.back(), intrinsics, glm::dvec2(x + 0.5, y + 0.5))};
}

}  // namespace refrax::ref
