#include "engine/ray_trace.h"

#include "engine/vk_buffer.h"
#include "engine/vk_commands.h"
#include "engine/vk_context.h"

namespace refrax {

RayTracePipelines createRayTracePipelines(Context& ctx) {
  RayTracePipelines p;
  p.closestTriangle = createComputePipeline(ctx, "trace_triangles", {kAccelStruct, kStorageBuffer, kStorageBuffer}, 4);
  p.candidates = createComputePipeline(ctx, "collect_candidates", {kAccelStruct, kStorageBuffer, kStorageBuffer, kStorageBuffer}, 8);
  return p;
}

std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene,
                                                  const std::vector<GpuRay>& rays) {
  if (rays.empty()) return {};
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer hitBuf = createBuffer(ctx, rays.size() * sizeof(GpuTriangleHit));
  uint32_t count = uint32_t(rays.size());
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdDispatch(cb, p.closestTriangle, {bind(scene), bind(rayBuf), bind(hitBuf)}, &count, groupsFor(count, 64));
  });
  return downloadVector<GpuTriangleHit>(ctx, hitBuf, rays.size());
}

CandidateLists collectCandidates(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene, const std::vector<GpuRay>& rays,
                                 uint32_t capacity) {
  CandidateLists out;
  out.capacity = capacity;
  if (rays.empty()) return out;
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer countBuf = createBuffer(ctx, rays.size() * 4);
  Buffer candBuf = createBuffer(ctx, rays.size() * capacity * 4);
  fillBuffer(ctx, candBuf, kNoHit);
  struct {
    uint32_t count, capacity;
  } push{uint32_t(rays.size()), capacity};
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdDispatch(cb, p.candidates, {bind(scene), bind(rayBuf), bind(countBuf), bind(candBuf)}, &push, groupsFor(push.count, 64));
  });
  out.counts = downloadVector<uint32_t>(ctx, countBuf, rays.size());
  out.candidates = downloadVector<uint32_t>(ctx, candBuf, rays.size() * capacity);
  return out;
}

}  // namespace refrax
