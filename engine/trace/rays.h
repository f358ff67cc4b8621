#pragma once
// The ray and hit records of shaders/include/rays.glsl (std430), declared there once:
// GpuRay {origin[3], tmin, dir[3], tmax}, GpuTriangleHit {t, u, v, primitive; kNoHit on a
// miss}, GpuRayGrad {dOrigin[3], pad0, dDir[3], pad1}.
#include "engine/base/gpu_layout.h"

namespace refrax {
#include "rays.glsl"
}  // namespace refrax
