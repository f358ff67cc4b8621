#pragma once
// Pinhole camera rays on the host, for rendering without refraction (water removal) and
// for tests: the same convention as shaders/include/camera.glsl (pixel centre (px+0.5,
// py+0.5) maps to forward + u*right - v*up, right/up pre-scaled by tan(half fov)).
#include <cstdint>
#include <vector>

#include "engine/rays.h"

namespace refrax {

struct PinholeCamera {  // mirrors camera.glsl PinholeCamera (std430)
  float position[4];
  float forward[4];
  float right[4];
  float up[4];
};

// Camera at `eye` looking at `target`, world up +z, square pixels, vertical and horizontal
// half-angle tangents tanHalfX and tanHalfX * height / width.
PinholeCamera lookAtCamera(const float eye[3], const float target[3], float tanHalfX, uint32_t width, uint32_t height);

// One ray per pixel, row-major from the top-left; unit directions.
std::vector<GpuRay> cameraRays(const PinholeCamera& camera, uint32_t width, uint32_t height, float tmin = 0.0f, float tmax = 1e6f);

}  // namespace refrax
