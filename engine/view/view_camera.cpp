#include "engine/view/view_camera.h"

#include <cmath>

#include "engine/base/error.h"

namespace refrax {

Camera cameraFromFly(const FlyCamera& cam, int width, int height) {
  if (width <= 0 || height <= 0) fail("camera with an empty image");
  if (!(cam.tanHalfFovY > 0)) fail("camera with a non-positive field of view");
  CameraBasis b = cameraBasis(cam);
  Camera c;
  c.cameraToWorld[0] = glm::dvec4(glm::dvec3(b.right), 0.0);
  c.cameraToWorld[1] = glm::dvec4(glm::dvec3(b.up), 0.0);
  c.cameraToWorld[2] = glm::dvec4(-glm::dvec3(b.forward), 0.0);
  c.cameraToWorld[3] = glm::dvec4(glm::dvec3(cam.position), 1.0);
  c.fy = 0.5 * height / double(cam.tanHalfFovY);
  c.fx = c.fy;
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  c.width = width;
  c.height = height;
  return c;
}


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
