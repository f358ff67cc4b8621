#pragma once
// Generic ray-query stages over lists of rays: closest triangle hit and AABB candidate
// listing. The building blocks the surface and Gaussian tracers specialise.
#include <vector>

#include "engine/rays.h"
#include "engine/vk_accel.h"
#include "engine/vk_pipeline.h"

namespace refrax {

struct Context;

struct RayTracePipelines {
  ComputePipeline closestTriangle;
  ComputePipeline candidates;
};
RayTracePipelines createRayTracePipelines(Context& ctx);

// Closest opaque hit of each ray against `scene` (a TLAS).
std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene,
                                                  const std::vector<GpuRay>& rays);

// Every AABB candidate reported along each ray, as primitive indices of the BLAS (up to
// `capacity` per ray; counts[i] is the full number).
struct CandidateLists {
  std::vector<uint32_t> counts;
  std::vector<uint32_t> candidates;  // rays.size() * capacity
  uint32_t capacity = 0;
};
CandidateLists collectCandidates(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene, const std::vector<GpuRay>& rays,
                                 uint32_t capacity);

}  // namespace refrax
