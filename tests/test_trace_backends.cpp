// The two trace backends side by side (engine/vk/vk_context.h TraceBackend): ray queries against
// acceleration structures, and compute shaders walking the water's grid and the proxies' box
// BVH. The same Gaussians and rays give the same hits in the same order, bit for bit; the
// same water gives the same triangles, within float rounding at edges.
#include <cmath>
#include <cstring>

#include "engine/height/analytic_height.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/vk/vk_context.h"
#include "tests/gaussian_test_scene.h"
#include "tests/gpu_test.h"
#include "tests/surface_test_util.h"

using namespace refrax;

namespace {

std::unique_ptr<Context> contextFor(TraceBackend backend) {
  ContextOptions o;
  o.trace = traceBackendName(backend);
  o.validation = true;
  return createContext(o);
}

struct GaussianTrace {
  std::vector<GpuTraceResult> results;
  std::vector<uint64_t> records;
};

GaussianTrace traceOn(Context& ctx, const GaussianSet& set, const std::vector<GpuRay>& rays, uint32_t K) {
  GaussianTracer tracer = createGaussianTracer(ctx, K);
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  HitRecords records = createHitRecords(ctx, uint32_t(rays.size()), 32);
  fillBuffer(ctx, records.buffer, 0);
  TraceOptions opt;
  opt.hitRecords = &records;
  GaussianTrace out;
  out.results = traceGaussians(ctx, tracer, proxies, dev, rays, opt);
  out.records = downloadVector<uint64_t>(ctx, records.buffer, rays.size() * 32);
  return out;
}

// A device without ray queries (the H200's driver, 2026-11-27) has one backend and nothing to
// compare; lavapipe, where CI runs, has both (tests/test_device_selection.cpp requires it). The
// cases make a context per backend whatever REFRAX_TRACE says, so they are in the doctest suite
// "rayquery-only": scripts/test.sh runs them in the first pass only (the compute pass would
// repeat the same comparison), and scripts/gpu-check.sh leaves them out on a device without
// ray queries. Run there anyway, one fails here saying why rather than passing having compared nothing.
void requireRayQueries(const Context& ctx) {
  REQUIRE_MESSAGE(ctx.caps.rayQuery, "'" << ctx.caps.name << "' lacks VK_KHR_ray_query: nothing to compare; leave the suite rayquery-only out");
}

}  // namespace

GPU_TEST_CASE("trace backends: the same Gaussians give the same hits in the same order, bit for bit" * doctest::test_suite("rayquery-only")) {
  requireRayQueries(ctx);
  auto rq = contextFor(TraceBackend::RayQuery), cs = contextFor(TraceBackend::Compute);
  GaussianSet set = randomGaussians(rng, 1500, test::testGaussianOptions());
  auto rays = test::raysIntoVolume(rng, 2000);
  for (uint32_t K : {4u, 48u}) {  // with rays that need several k-buffer rounds, and with one
    CAPTURE(K);
    GaussianTrace a = traceOn(*rq, set, rays, K), b = traceOn(*cs, set, rays, K);
    REQUIRE(a.results.size() == b.results.size());
    size_t differing = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); i++) {
      differing += std::memcmp(&a.results[i], &b.results[i], sizeof(GpuTraceResult)) != 0;
      hits += a.results[i].hits;
    }
    CHECK(hits > 5 * rays.size());  // the scene is not empty
    CHECK(differing == 0);
    CHECK(a.records == b.records);  // every blended hit, in order: Gaussian id and alpha
  }
  CHECK(rq->validationMessageCount.load() == 0);
  CHECK(cs->validationMessageCount.load() == 0);
}

GPU_TEST_CASE("trace backends: the same water gives the same triangles, t and refracted rays" * doctest::test_suite("rayquery-only")) {
  requireRayQueries(ctx);
  auto rq = contextFor(TraceBackend::RayQuery), cs = contextFor(TraceBackend::Compute);
  AnalyticWaves waves = randomWaves(rng, 0.1f, 5.0f);
  std::vector<GpuRay> rays = test::raysFromAbove(rng, 3000, 1.1f);
  WaterSurfaceConfig cfg;
  cfg.gridCells = 24;
  cfg.subdivisionLevels = 2;
  cfg.maxRays = uint32_t(rays.size());
  test::SurfaceRun run[2];
  Context* contexts[2] = {rq.get(), cs.get()};
  for (int k = 0; k < 2; k++) {
    Context& c = *contexts[k];
    AnalyticHeightField field = createAnalyticHeightField(c, waves);
    WaterSurface ws = createWaterSurface(c, cfg);
    test::updateSurface(c, ws, heightSource(field));
    run[k] = test::runSurface(c, ws, heightSource(field), rays);
  }
  size_t hits = 0, otherTriangle = 0, hitMiss = 0;
  double worstT = 0, worstRay = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    const SurfaceRecord &a = run[0].recordList[i], &b = run[1].recordList[i];
    bool ha = surfaceRecordFlags(a) & kSurfaceHit, hb = surfaceRecordFlags(b) & kSurfaceHit;
    hitMiss += ha != hb;
    if (!ha || !hb) continue;
    hits++;
    if (a.cell != b.cell || (a.info & 0xFFu) != (b.info & 0xFFu)) {
      otherTriangle++;  // a ray through a shared edge may land on either neighbour
      continue;
    }
    worstT = std::max(worstT, double(std::abs(a.t - b.t)) / std::max(1.0, double(std::abs(a.t))));
    for (int c = 0; c < 3; c++) {
      worstRay = std::max(worstRay, double(std::abs(run[0].refractedRays[i].origin[c] - run[1].refractedRays[i].origin[c])));
      worstRay = std::max(worstRay, double(std::abs(run[0].refractedRays[i].dir[c] - run[1].refractedRays[i].dir[c])));
    }
  }
  INFO("hits " << hits << ", other triangle " << otherTriangle << ", hit/miss " << hitMiss << ", worst t " << worstT << ", worst ray "
               << worstRay);
  CHECK(hits > rays.size() / 2);
  CHECK(hitMiss <= 2);
  CHECK(otherTriangle * 200 <= hits);
  CHECK(worstT < 1e-5);
  CHECK(worstRay < 1e-4);
  CHECK(rq->validationMessageCount.load() == 0);
  CHECK(cs->validationMessageCount.load() == 0);
}
