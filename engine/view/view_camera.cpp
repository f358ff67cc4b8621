#include "engine/view/view_camera.h"

#include <cmath>

#include "engine/base/error.h"

namespace refrax {

FlyCamera flyFromCamera(const Camera& camera, const FlyCamera& like) {
  FlyCamera f = like;
  glm::vec3 position(camera.position()), forward(-glm::normalize(camera.back()));
  lookAt(f, position, position + forward);
  f.tanHalfFovY = float(0.5 * camera.height / camera.fy);
  return f;
}

Camera resizedCamera(const Camera& camera, int width, int height) {
  if (width <= 0 || height <= 0) fail("camera: the image size must be positive");
  if (camera.width <= 0 || camera.height <= 0) fail("camera: the source camera has no image size");
  Camera c = camera;
  double sx = double(width) / camera.width, sy = double(height) / camera.height;
  c.fx *= sx;
  c.cx *= sx;
  c.fy *= sy;
  c.cy *= sy;
  c.width = width;
  c.height = height;
  return c;
}

}  // namespace refrax
