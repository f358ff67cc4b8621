#include "engine/view/fly_camera.h"

#include <algorithm>
#include <cmath>

namespace refrax {

namespace {
const float kMaxPitch = 1.55f;  // just short of straight up/down, where yaw is undefined
}

CameraBasis cameraBasis(const FlyCamera& cam) {
  CameraBasis b;
  b.forward = {std::cos(cam.pitch) * std::cos(cam.yaw), std::cos(cam.pitch) * std::sin(cam.yaw), std::sin(cam.pitch)};
  b.right = glm::normalize(glm::cross(b.forward, glm::vec3(0, 0, 1)));
  b.up = glm::cross(b.right, b.forward);
  return b;
}

void flyMove(FlyCamera& cam, float forward, float right, float up, float dt) {
  CameraBasis b = cameraBasis(cam);
  glm::vec3 step = (b.forward * forward + b.right * right + glm::vec3(0, 0, 1) * up) * (cam.speed * dt);
  cam.position += step;
  if (cam.orbit) cam.orbitTarget += b.right * right * (cam.speed * dt) + glm::vec3(0, 0, up * cam.speed * dt);
}

void flyLook(FlyCamera& cam, float dYaw, float dPitch) {
  if (!cam.orbit) {
    cam.yaw += dYaw;
    cam.pitch = std::clamp(cam.pitch + dPitch, -kMaxPitch, kMaxPitch);
    return;
  }
  float distance = glm::length(cam.position - cam.orbitTarget);
  cam.yaw += dYaw;
  cam.pitch = std::clamp(cam.pitch + dPitch, -kMaxPitch, kMaxPitch);
  cam.position = cam.orbitTarget - cameraBasis(cam).forward * distance;
}

void lookAt(FlyCamera& cam, const glm::vec3& position, const glm::vec3& target) {
  glm::vec3 d = glm::normalize(target - position);
  cam.position = position;
  cam.yaw = std::atan2(d.y, d.x);
  cam.pitch = std::clamp(std::asin(std::clamp(d.z, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  cam.orbitTarget = target;
}

}  // namespace refrax

namespace refrax {

GpuPinholeCamera toGpuCamera(const FlyCamera& cam, uint32_t width, uint32_t height) {
  CameraBasis b = cameraBasis(cam);
  float tanY = cam.tanHalfFovY, tanX = tanY * float(width) / float(height);
  GpuPinholeCamera g{};
  for (int a = 0; a < 3; a++) {
    g.position[a] = cam.position[a];
    g.forward[a] = b.forward[a];
    g.right[a] = b.right[a] * tanX;
    g.up[a] = b.up[a] * tanY;
  }
  return g;
}

}  // namespace refrax

#include <cstdio>

#include "engine/base/error.h"

namespace refrax {

FlyCamera parseLookAt(const std::string& text) {
  float v[6];
  char tail;
  if (std::sscanf(text.c_str(), "%f,%f,%f,%f,%f,%f%c", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &tail) != 6)
    fail("camera '" + text + "' must be x,y,z,targetX,targetY,targetZ");
  for (float x : v)
    if (!std::isfinite(x)) fail("camera '" + text + "' is not finite");
  if (v[0] == v[3] && v[1] == v[4] && v[2] == v[5]) fail("camera '" + text + "' looks at its own position");
  FlyCamera cam;
  lookAt(cam, {v[0], v[1], v[2]}, {v[3], v[4], v[5]});
  return cam;
}

}  // namespace refrax
