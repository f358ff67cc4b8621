#pragma once
// CPU double reference of the camera rays (engine/camera/camera_rays.h).
#include "engine/camera/camera.h"

namespace refrax::ref {

struct CameraRay {
  glm::dvec3 origin, dir;
};

// The ray through the centre of pixel (x, y), through the camera's lens.
inline CameraRay cameraRay(const Camera& c, int x, int y) { return {c.position(), c.rayDirection(x + 0.5, y + 0.5)}; }

}  // namespace refrax::ref
