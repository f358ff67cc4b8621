#include "engine/trace/ray_trace.h"

#include "engine/trace/triangle_bvh.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {
bool computeBackend(const Context& ctx) { return ctx.trace == TraceBackend::Compute; }

std::vector<GpuTriangleHit> closestTriangles(Context& ctx, const RayTracePipelines& p, const Binding& scene, const TraceScene* mesh,
                                             const std::vector<GpuRay>& rays) {
  if (rays.empty()) return {};
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer hitBuf = createBuffer(ctx, rays.size() * sizeof(GpuTriangleHit));
  uint32_t count = uint32_t(rays.size());
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    if (mesh && computeBackend(ctx))
      cmdDispatch(cb, p.closestTriangle, {scene, bind(rayBuf), bind(hitBuf), bind(mesh->vertices), bind(mesh->indices)}, &count,
                  groupsFor(count, 64));
    else
      cmdDispatch(cb, p.closestTriangle, {scene, bind(rayBuf), bind(hitBuf)}, &count, groupsFor(count, 64));
  });
  std::vector<GpuTriangleHit> hits = downloadVector<GpuTriangleHit>(ctx, hitBuf, rays.size());
  if (mesh && !mesh->order.empty())
    for (GpuTriangleHit& h : hits)
      if (h.primitive != kNoHit) h.primitive = mesh->order[h.primitive];
  return hits;
}
}  // namespace

RayTracePipelines createRayTracePipelines(Context& ctx) {
  RayTracePipelines p;
  auto B = kStorageBuffer;
  if (computeBackend(ctx)) {
    p.closestTriangle = createComputePipeline(ctx, "trace_triangles_compute", {B, B, B, B, B}, 4);
    p.candidates = createComputePipeline(ctx, "collect_candidates_compute", {B, B, B, B}, 8);
  } else {
    p.closestTriangle = createComputePipeline(ctx, "trace_triangles", {kAccelStruct, B, B}, 4);
    p.candidates = createComputePipeline(ctx, "collect_candidates", {kAccelStruct, B, B, B}, 8);
  }
  return p;
}

TraceScene buildTriangleScene(Context& ctx, const std::vector<float>& vertices, const std::vector<uint32_t>& indices) {
  TraceScene s;
  if (computeBackend(ctx)) {
    s.order = medianSplitOrder(triangleBoxes(vertices, indices));
    std::vector<uint32_t> ordered(indices.size());
    for (size_t k = 0; k < s.order.size(); k++)
      for (int c = 0; c < 3; c++) ordered[3 * k + c] = indices[3 * size_t(s.order[k]) + c];
    s.vertices = createBufferFrom(ctx, vertices);
    s.indices = createBufferFrom(ctx, ordered);
    s.bvh = createTriangleBvh(ctx, vertices, ordered);
    return s;
  }
  s.vertices = createBufferFrom(ctx, vertices, kAccelInput);
  s.indices = createBufferFrom(ctx, indices, kAccelInput);
  s.blas = createTriangleBlas(ctx, s.vertices, uint32_t(vertices.size() / 3), 12, s.indices, uint32_t(indices.size() / 3));
  s.top = createTopLevel(ctx, {makeInstance(s.blas, 0)});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.blas);
    cmdBarrier(cb);
    cmdBuild(cb, s.top.tlas);
  });
  return s;
}

TraceScene buildBoxScene(Context& ctx, const std::vector<Box>& boxes) {
  TraceScene s;
  Buffer boxBuffer = createBufferFrom(ctx, boxes, kAccelInput);
  if (computeBackend(ctx)) {
    s.bvh = createBoxBvh(ctx, uint32_t(boxes.size()));
    ComputePipeline refit = createBvhRefitPipeline(ctx);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRefitBoxBvh(cb, refit, s.bvh, boxBuffer); });
    return s;
  }
  s.blas = createAabbBlas(ctx, boxBuffer, uint32_t(boxes.size()));
  s.top = createTopLevel(ctx, {makeInstance(s.blas, 0)});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.blas);
    cmdBarrier(cb);
    cmdBuild(cb, s.top.tlas);
  });
  s.vertices = std::move(boxBuffer);  // the BLAS reads its input at build time only; kept alive with the scene all the same
  return s;
}

std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const TraceScene& scene,
                                                  const std::vector<GpuRay>& rays) {
  return closestTriangles(ctx, p, scene.bvh.leaves ? bind(scene.bvh.nodes) : bind(scene.top.tlas), &scene, rays);
}

std::vector<GpuTriangleHit> traceClosestTriangles(Context& ctx, const RayTracePipelines& p, const AccelStruct& scene,
                                                  const std::vector<GpuRay>& rays) {
  return closestTriangles(ctx, p, bind(scene), nullptr, rays);
}

CandidateLists collectCandidates(Context& ctx, const RayTracePipelines& p, const TraceScene& scene, const std::vector<GpuRay>& rays,
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
  const Binding sceneBinding = scene.bvh.leaves ? bind(scene.bvh.nodes) : bind(scene.top.tlas);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdDispatch(cb, p.candidates, {sceneBinding, bind(rayBuf), bind(countBuf), bind(candBuf)}, &push, groupsFor(push.count, 64));
  });
  out.counts = downloadVector<uint32_t>(ctx, countBuf, rays.size());
  out.candidates = downloadVector<uint32_t>(ctx, candBuf, rays.size() * capacity);
  return out;
}

}  // namespace refrax
