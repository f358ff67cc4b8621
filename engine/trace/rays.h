#pragma once
// Host mirrors of shaders/include/rays.glsl (std430).
#include <cstdint>

namespace refrax {

struct GpuRay {
  float origin[3];
  float tmin;
  float dir[3];
  float tmax;
};

struct GpuTriangleHit {
  float t;  // < 0 on a miss
  float u, v;
  uint32_t primitive;  // kNoHit on a miss
};

constexpr uint32_t kNoHit = 0xFFFFFFFFu;

// dLoss/d(origin) and dLoss/d(direction) of one ray.
struct GpuRayGrad {
  float dOrigin[3];
  float pad0;
  float dDir[3];
  float pad1;
};
static_assert(sizeof(GpuRayGrad) == 32, "GpuRayGrad must match the std430 RayGrad");

static_assert(sizeof(GpuRay) == 32, "GpuRay must match the std430 Ray");
static_assert(sizeof(GpuTriangleHit) == 16, "GpuTriangleHit must match the std430 TriangleHit");

}  // namespace refrax
