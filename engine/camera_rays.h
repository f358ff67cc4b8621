#pragma once
// Pinhole camera rays on the host, for rendering without refraction (water removal) and
// for tests: the convention of shaders/include/camera.glsl (pixel centre (px+0.5, py+0.5)
// maps to forward + u*right - v*up, right/up pre-scaled by the half-fov tangents), with
// the camera from engine/fly_camera.h.
#include <cstdint>
#include <vector>

#include "engine/fly_camera.h"
#include "engine/rays.h"

namespace refrax {

// One ray per pixel, row-major from the top-left; unit directions.
std::vector<GpuRay> cameraRays(const GpuPinholeCamera& camera, uint32_t width, uint32_t height, float tmin = 0.0f, float tmax = 1e6f);

}  // namespace refrax
