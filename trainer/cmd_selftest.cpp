// refrax selftest: traces a few thousand rays on the chosen device against a triangle
// surface and a set of boxes, and checks every answer against the CPU reference.
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/surface/grid_mesh.h"
#include "engine/trace/presort.h"
#include "engine/trace/ray_trace.h"
#include "engine/reference/check_trace.h"
#include "engine/reference/random_rays.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runSelftest(const cli::Args& args) {
  auto ctx = openContext(args);
  RayTracePipelines pipelines = createRayTracePipelines(*ctx);
  std::mt19937 rng(uint32_t(args.getInt("seed", 1)));
  bool ok = true;

  // 1. A rippled triangle surface.
  GridMesh mesh = makeGridMesh(24, 24, -1, -1, 1, 1, [](float x, float y) { return 0.05f * std::sin(6 * x) * std::cos(4 * y); });
  TraceScene surface = buildTriangleScene(*ctx, mesh.vertices, mesh.indices);
  auto rays = ref::randomRays(rng, 2000, {{-1.5f, -1.5f, 1.0f}, {1.5f, 1.5f, 2.0f}, {-1.2f, -1.2f, -0.1f}, {1.2f, 1.2f, 0.1f}});
  auto hits = traceClosestTriangles(*ctx, pipelines, surface, rays);
  auto tri = ref::compareTriangleHits(mesh.vertices, mesh.indices, rays, hits);
  bool triOk = tri.ok(1e-5);
  std::printf("triangles: %zu rays, %zu hits (cpu %zu), worst t err %.2e, barycentric err %.2e (as distance %.2e): %s\n",
              tri.rays, tri.gpuHits, tri.cpuHits, tri.worstTRel, tri.worstBary, tri.worstBaryPoint, triOk ? "ok" : ("FAILED: " + tri.firstProblem).c_str());
  ok &= triOk;

  // 2. Boxes (Gaussian proxies), presorted as the engine always does for lavapipe.
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<Box> boxes(500);
  for (auto& b : boxes) {
    float c[3] = {U(rng) * 2 - 1, U(rng) * 2 - 1, -U(rng)}, h = 0.01f + 0.05f * U(rng);
    b = {c[0] - h, c[1] - h, c[2] - h, c[0] + h, c[1] + h, c[2] + h};
  }
  boxes = permuted(boxes, medianSplitOrder(boxes));
  TraceScene boxScene = buildBoxScene(*ctx, boxes);
  auto boxRays = ref::randomRays(rng, 1000, {{-1.5f, -1.5f, 1.0f}, {1.5f, 1.5f, 2.0f}, {-1, -1, -1}, {1, 1, 0}});
  auto cand = collectCandidates(*ctx, pipelines, boxScene, boxRays, 256);
  auto rep = ref::compareCandidates(boxes, boxRays, cand.counts, cand.candidates, cand.capacity);
  bool boxOk = rep.missingPairs == 0 && rep.overflowRays == 0;
  std::printf("boxes: %zu rays, %.1f candidates per ray, %zu overlaps expected, %zu missing: %s\n", rep.rays, rep.meanCandidates,
              rep.expectedPairs, rep.missingPairs, boxOk ? "ok" : ("FAILED: " + rep.firstProblem).c_str());
  ok &= boxOk;

  int messages = ctx->validationMessageCount.load();
  if (ctx->validation) std::printf("validation messages: %d\n", messages);
  ok &= messages == 0;
  std::printf("selftest %s on %s (%s trace)\n", ok ? "passed" : "FAILED", ctx->caps.name.c_str(), traceBackendName(ctx->trace));
  return ok ? 0 : 1;
}

std::vector<cli::Option> selftestOptions() {
  auto o = cli::deviceOptions();
  o.push_back({"seed", "N", "random seed for the rays and boxes", "1"});
  return o;
}

REFRAX_COMMAND({"selftest", "trace a few thousand rays on the device and check them against the CPU reference",
                "refrax selftest [--device NAME|INDEX] [--validation] [--seed N]", selftestOptions(), runSelftest});

}  // namespace
}  // namespace refrax
