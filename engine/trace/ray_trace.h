#pragma once
// Generic ray stages over lists of rays: closest triangle hit and AABB candidate listing, on
// either trace backend (engine/vk/vk_context.h TraceBackend). The building blocks the surface and
// Gaussian tracers specialise; `refrax selftest` and the tests check them against the CPU.
#include <vector>

#include "engine/trace/box_bvh.h"
#include "engine/trace/presort.h"
#include "engine/trace/rays.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct RayTracePipelines {
  ComputePipeline closestTriangle;
  ComputePipeline candidates;
};
RayTracePipelines createRayTracePipelines(Context& ctx);

// Triangles or boxes made traceable on the context's backend: BLAS + TLAS for ray queries, or
// a box BVH for the compute backend. Results name the primitives as the caller gave them
// (the compute backend reorders triangles into the BVH's order and maps hits back).
struct TraceScene {
  AccelStruct blas;
  TopLevel top;
  BoxBvh bvh;
  std::vector<uint32_t> order;  // compute backend, triangles: BVH slot -> the caller's triangle
  Buffer vertices, indices;     // triangles (in BVH order on the compute backend)
};
TraceScene buildTriangleScene(Context& ctx, const std::vector<float>& vertices, const std::vector<uint32_t>& indices);
TraceScene buildBoxScene(Context& ctx, const std::vector<Box>& boxes);

// Closest opaque hit of each ray.
std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const TraceScene& scene,
                                                  const std::vector<GpuRay>& rays);
// Against a TLAS the caller built (ray-query backend only: tests of the acceleration structures).
std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene,
                                                  const std::vector<GpuRay>& rays);

// Every AABB candidate reported along each ray, as box indices (up to `capacity` per ray;
// counts[i] is the full number).
struct CandidateLists {
  std::vector<uint32_t> counts;
  std::vector<uint32_t> candidates;  // rays.size() * capacity
  uint32_t capacity = 0;
};
CandidateLists collectCandidates(Context& ctx, const RayTracePipelines& p, const TraceScene& scene, const std::vector<GpuRay>& rays,
                                 uint32_t capacity);

}  // namespace refrax
