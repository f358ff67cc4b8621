#pragma once
// The viewer's camera: a fly camera (position + yaw/pitch, Z up) with an orbit mode that
// circles a target. Pure math, so tests and `refrax render` camera paths share it.
#include <cstdint>
#include <string>
#include <glm/glm.hpp>

#include "engine/base/gpu_layout.h"

namespace refrax {

struct FlyCamera {
  glm::vec3 position{0.0f, -2.0f, 1.5f};
  float yaw = 1.5707963f;  // radians; 0 looks along +X, pi/2 along +Y
  float pitch = -0.6f;     // radians; negative looks down
  float tanHalfFovY = 0.4f;
  float speed = 1.0f;  // world units per second
  bool orbit = false;
  glm::vec3 orbitTarget{0.0f};
};

struct CameraBasis {
  glm::vec3 forward, right, up;  // unit, right-handed: right = forward x Z
};

CameraBasis cameraBasis(const FlyCamera& cam);
// Moves along the view (forward, right, world up) by the given amounts times speed*dt.
void flyMove(FlyCamera& cam, float forward, float right, float up, float dt);
// Mouse look by (dx, dy) radians; in orbit mode the camera circles the target instead.
void flyLook(FlyCamera& cam, float dYaw, float dPitch);
// Points the camera from `position` at `target`.
void lookAt(FlyCamera& cam, const glm::vec3& position, const glm::vec3& target);

}  // namespace refrax

namespace refrax {

// GpuPinholeCamera {position[4], forward[4], right[4], up[4]}, declared once in
// shaders/include/pinhole_camera.glsl: right/up pre-scaled by the tangents of the half fields
// of view (square pixels: tanHalfX = tanHalfY * w / h).
#include "pinhole_camera.glsl"
GpuPinholeCamera toGpuCamera(const FlyCamera& cam, uint32_t width, uint32_t height);

}  // namespace refrax

namespace refrax {
// "x,y,z,tx,ty,tz": a camera at (x,y,z) looking at (tx,ty,tz); refrax::Error when malformed.
FlyCamera parseLookAt(const std::string& text);
}  // namespace refrax
