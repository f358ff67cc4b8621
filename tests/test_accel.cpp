// Ray queries against triangle and AABB acceleration structures, build and refit, all
// checked against brute-force CPU double-precision references. The closest-hit and candidate
// cases run on the context's trace backend (REFRAX_TRACE=compute: the box BVHs of
// engine/trace/box_bvh.h); the refit cases are the acceleration structures' own.
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/surface/grid_mesh.h"
#include "engine/trace/presort.h"
#include "engine/trace/ray_trace.h"
#include "engine/reference/check_trace.h"
#include "engine/reference/random_rays.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

struct TriangleScene {
  Buffer vertices, indices;
  AccelStruct blas;
  TopLevel top;
};

TriangleScene buildTriangleScene(Context& ctx, const GridMesh& mesh, bool allowUpdate) {
  TriangleScene s;
  s.vertices = createBufferFrom(ctx, mesh.vertices, kAccelInput);
  s.indices = createBufferFrom(ctx, mesh.indices, kAccelInput);
  s.blas = createTriangleBlas(ctx, s.vertices, mesh.vertexCount(), 12, s.indices, mesh.triangleCount(), {allowUpdate});
  s.top = createTopLevel(ctx, {makeInstance(s.blas, 0)}, {allowUpdate});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.blas);
    cmdBarrier(cb);
    cmdBuild(cb, s.top.tlas);
  });
  return s;
}

std::vector<Box> randomBoxes(std::mt19937& rng, size_t n) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<Box> boxes(n);
  for (auto& b : boxes) {
    float c[3] = {U(rng) * 2 - 1, U(rng) * 2 - 1, -U(rng)};
    float h[3] = {0.005f + 0.04f * U(rng), 0.005f + 0.04f * U(rng), 0.005f + 0.04f * U(rng)};
    b = {c[0] - h[0], c[1] - h[1], c[2] - h[2], c[0] + h[0], c[1] + h[1], c[2] + h[2]};
  }
  return boxes;
}

const ref::RayBox kFromAbove{{-1.5f, -1.5f, 0.8f}, {1.5f, 1.5f, 2.0f}, {-1.1f, -1.1f, -0.2f}, {1.1f, 1.1f, 0.2f}};

}  // namespace

// The refit cases are the acceleration structures' own: the compute trace backend builds none.
// They are in the doctest suite "rayquery-only", which scripts/test.sh leaves out of the compute
// pass by name (and scripts/gpu-check.sh out of its compute run), so no pass counts one that
// checked nothing; run on the compute backend anyway, one fails here saying why.
void requireRayQueries(Context& ctx) {
  REQUIRE_MESSAGE(ctx.trace == TraceBackend::RayQuery,
                  "a rayquery-only case on the compute trace backend, which builds no acceleration structures: leave the suite out");
}

GPU_TEST_CASE("10k random rays against a triangle BLAS match Moller-Trumbore") {
  std::uniform_real_distribution<float> U(0.5f, 1.5f);
  float a = U(rng), b = U(rng);
  GridMesh mesh = makeGridMesh(40, 40, -1, -1, 1, 1, [&](float x, float y) { return 0.08f * std::sin(5 * a * x) * std::cos(4 * b * y); });
  TraceScene scene = buildTriangleScene(ctx, mesh.vertices, mesh.indices);
  RayTracePipelines p = createRayTracePipelines(ctx);
  auto rays = ref::randomRays(rng, 10000, kFromAbove);
  auto hits = traceClosestTriangles(ctx, p, scene, rays);
  auto rep = ref::compareTriangleHits(mesh.vertices, mesh.indices, rays, hits);
  INFO("first problem: " << rep.firstProblem);
  CHECK(rep.cpuHits > 5000);  // the rays mostly hit: the comparison means something
  CHECK(rep.hitMissDisagree == 0);
  CHECK(rep.wrongTriangle == 0);
  CHECK(rep.worstTRel <= 1e-5);
  CHECK(rep.worstBaryPoint <= 1e-5);
  // Raw barycentrics of 0.05-wide triangles: the hit point may move by the relative bound
  // above times max(t, 1), which is that over 0.05 in barycentrics (seed 1122073542 reached
  // 3.2e-4 with the point within 5.1e-6 of the reference).
  double maxT = 1.0;
  for (const GpuTriangleHit& h : hits)
    if (h.primitive != kNoHit) maxT = std::max(maxT, double(h.t));
  CHECK(rep.worstBary <= 1e-5 * maxT / (2.0 / 40));
  CHECK(rep.edgeAmbiguous < 20);
}

GPU_TEST_CASE("ray tmin/tmax limit triangle hits") {
  GridMesh mesh = makeGridMesh(4, 4, -1, -1, 1, 1);
  TraceScene scene = buildTriangleScene(ctx, mesh.vertices, mesh.indices);
  RayTracePipelines p = createRayTracePipelines(ctx);
  // straight down from z=1 onto the z=0 plane: t = 1
  std::vector<GpuRay> rays = {{{0.1f, 0.2f, 1}, 0, {0, 0, -1}, 2},    // hit at 1
                              {{0.1f, 0.2f, 1}, 0, {0, 0, -1}, 0.5f}, // tmax before: miss
                              {{0.1f, 0.2f, 1}, 1.5f, {0, 0, -1}, 3}, // tmin after: miss
                              {{0.1f, 0.2f, 1}, 0, {0, 0, 1}, 3}};    // pointing away: miss
  auto hits = traceClosestTriangles(ctx, p, scene, rays);
  CHECK(hits[0].primitive != kNoHit);
  CHECK(hits[0].t == doctest::Approx(1.0f).epsilon(1e-6));
  for (int i = 1; i < 4; i++) CHECK(hits[i].primitive == kNoHit);
}

GPU_TEST_CASE("refit after moving vertices gives the same hits as a fresh build" * doctest::test_suite("rayquery-only")) {
  requireRayQueries(ctx);
  GridMesh mesh = makeGridMesh(32, 32, -1, -1, 1, 1, [](float x, float y) { return 0.05f * std::sin(4 * x + y); });
  TriangleScene refitted = buildTriangleScene(ctx, mesh, true);
  // move every vertex: a different wave
  std::uniform_real_distribution<float> U(2.0f, 6.0f);
  float k = U(rng);
  GridMesh moved = mesh;
  for (size_t i = 0; i < moved.vertices.size(); i += 3)
    moved.vertices[i + 2] = 0.1f * std::cos(k * moved.vertices[i] - 2 * moved.vertices[i + 1]);
  upload(ctx, refitted.vertices, moved.vertices.data(), moved.vertices.size() * 4);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdRefit(cb, refitted.blas);
    cmdBarrier(cb);
    cmdRefit(cb, refitted.top.tlas);
  });
  TriangleScene fresh = buildTriangleScene(ctx, moved, false);
  RayTracePipelines p = createRayTracePipelines(ctx);
  auto rays = ref::randomRays(rng, 5000, kFromAbove);
  auto a = traceClosestTriangles(ctx, p, refitted.top.tlas, rays);
  auto b = traceClosestTriangles(ctx, p, fresh.top.tlas, rays);
  size_t differ = 0;
  for (size_t i = 0; i < rays.size(); i++)
    differ += a[i].primitive != b[i].primitive || std::fabs(a[i].t - b[i].t) > 1e-6f * std::max(1.0f, std::fabs(b[i].t));
  CHECK(differ == 0);
  // and both agree with the CPU on the moved surface (the refit really moved it)
  auto rep = ref::compareTriangleHits(moved.vertices, moved.indices, rays, a);
  INFO(rep.firstProblem);
  CHECK(rep.ok(1e-5));
  auto stale = ref::compareTriangleHits(mesh.vertices, mesh.indices, rays, a);
  CHECK_FALSE(stale.ok(1e-5));
}

GPU_TEST_CASE("refit without allowUpdate is refused" * doctest::test_suite("rayquery-only")) {
  requireRayQueries(ctx);
  GridMesh mesh = makeGridMesh(2, 2, -1, -1, 1, 1);
  TriangleScene scene = buildTriangleScene(ctx, mesh, false);
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRefit(cb, scene.blas); }), Error);
}

namespace {
void checkAabbCandidates(Context& ctx, std::mt19937& rng, bool presort) {
  std::vector<Box> original = randomBoxes(rng, 2000);
  std::vector<uint32_t> order(original.size());
  for (uint32_t i = 0; i < order.size(); i++) order[i] = i;
  if (presort) order = medianSplitOrder(original);
  std::vector<Box> submitted = permuted(original, order);
  TraceScene scene = buildBoxScene(ctx, submitted);
  RayTracePipelines p = createRayTracePipelines(ctx);
  auto rays = ref::randomRays(rng, 2000, {{-1.5f, -1.5f, 0.5f}, {1.5f, 1.5f, 2.0f}, {-1, -1, -1}, {1, 1, 0}});
  auto cand = collectCandidates(ctx, p, scene, rays, 512);
  // map primitive indices back to the original boxes through the permutation
  for (auto& c : cand.candidates)
    if (c != kNoHit) c = order[c];
  auto rep = ref::compareCandidates(original, rays, cand.counts, cand.candidates, cand.capacity);
  INFO(rep.firstProblem);
  CHECK(rep.expectedPairs > 2000);
  CHECK(rep.overflowRays == 0);
  CHECK(rep.missingPairs == 0);
  // Grazing pairs are the ray chords within the margin of a face: about 0.1% of the pairs at
  // 1e-5 (5 of 4,234 on seed 1243296222), tens of percent with a margin that hides real misses
  // (1e-2: 2,721 against 1,492).
  INFO(rep.grazingPairs << " grazing pairs of " << rep.expectedPairs);
  CHECK(rep.grazingPairs * 100 < rep.expectedPairs);
}
}  // namespace

GPU_TEST_CASE("every overlapping box is an AABB candidate, presorted") { checkAabbCandidates(ctx, rng, true); }
GPU_TEST_CASE("every overlapping box is an AABB candidate, input order") { checkAabbCandidates(ctx, rng, false); }

TEST_CASE("median-split order is a permutation that groups nearby boxes") {
  std::mt19937 rng(refrax::test::freshSeed());
  auto boxes = randomBoxes(rng, 1000);
  auto order = medianSplitOrder(boxes);
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < sorted.size(); i++) REQUIRE(sorted[i] == i);
  // neighbours in the order are much closer than neighbours in random order
  auto meanGap = [&](const std::vector<uint32_t>& ord) {
    double s = 0;
    for (size_t k = 1; k < ord.size(); k++) {
      const Box &a = boxes[ord[k - 1]], &b = boxes[ord[k]];
      s += std::hypot(a.minX - b.minX, a.minY - b.minY, a.minZ - b.minZ);
    }
    return s / double(ord.size() - 1);
  };
  std::vector<uint32_t> identity(boxes.size());
  for (uint32_t i = 0; i < identity.size(); i++) identity[i] = i;
  CHECK(meanGap(order) < 0.5 * meanGap(identity));
}

TEST_CASE("Morton cell order visits every cell once") {
  auto order = mortonCellOrder(13, 7);
  std::sort(order.begin(), order.end());
  REQUIRE(order.size() == 91);
  for (uint32_t i = 0; i < order.size(); i++) CHECK(order[i] == i);
}
