// The water surface across several traces of one set of heights (engine/surface/water_surface.h):
// the lattice points stay cached until cmdUpdateSurface, and dL/dheight summed over several
// traces and pushed into the MLP once equals the traces' backwards pushed one by one.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/surface/height_field_source.h"
#include "tests/gpu_test.h"
#include "tests/surface_test_util.h"

using namespace refrax;

namespace {

HeightFieldConfig smallField() {
  HeightFieldConfig hc;
  hc.width = 16;
  hc.hiddenLayers = 2;
  hc.lastLayerInitRange = 0.05f;
  return hc;
}

WaterSurfaceConfig smallSurface(uint32_t maxRays) {
  WaterSurfaceConfig cfg;
  cfg.gridCells = 10;
  cfg.subdivisionLevels = 2;
  cfg.maxRays = maxRays;
  return cfg;
}

std::vector<GpuRayGrad> rayGradients(std::mt19937& rng, size_t n) {
  std::normal_distribution<float> N(0, 1);
  std::vector<GpuRayGrad> g(n);
  for (auto& x : g) {
    for (int a = 0; a < 3; a++) {
      x.dOrigin[a] = N(rng);
      x.dDir[a] = N(rng);
    }
    x.pad0 = x.pad1 = 0;
  }
  return g;
}

bool sameBits(const std::vector<GpuRay>& a, const std::vector<GpuRay>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(GpuRay)) == 0;
}

double relativeDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double scale = 0, diff = 0;
  for (size_t i = 0; i < a.size(); i++) {
    scale = std::max(scale, std::abs(double(b[i])));
    diff = std::max(diff, std::abs(double(a[i]) - double(b[i])));
  }
  return scale > 0 ? diff / scale : (diff > 0 ? INFINITY : 0.0);
}

}  // namespace

GPU_TEST_CASE("surface point cache: later traces of the same heights evaluate only new points and refract as a fresh trace") {
  const uint32_t n = 120;
  HeightField hf = createHeightField(ctx, smallField(), rng());
  WaterSurface ws = createWaterSurface(ctx, smallSurface(n));
  test::updateSurface(ctx, ws, heightSource(hf));
  std::vector<GpuRay> raysA = test::raysFromAbove(rng, n, 0.5f), raysB = test::raysFromAbove(rng, n, 0.9f);

  test::SurfaceRun firstA = test::runSurface(ctx, ws, heightSource(hf), raysA);
  const uint32_t pointsA = firstA.counters.points;
  CHECK(pointsA > 100);
  test::SurfaceRun b = test::runSurface(ctx, ws, heightSource(hf), raysB);
  CHECK(b.counters.points > pointsA);  // B's own points were added to A's
  test::SurfaceRun againA = test::runSurface(ctx, ws, heightSource(hf), raysA);
  CHECK(againA.counters.points == b.counters.points);  // nothing new to evaluate
  CHECK(sameBits(againA.refractedRays, firstA.refractedRays));

  // New heights: the cache is emptied, and the trace matches a surface that never had one.
  std::vector<float> w = downloadWeights(ctx, hf);
  for (float& x : w) x *= 1.5f;
  uploadWeights(ctx, hf, w);
  test::updateSurface(ctx, ws, heightSource(hf));
  CHECK(ws.cachedPoints == 0);
  test::SurfaceRun changedA = test::runSurface(ctx, ws, heightSource(hf), raysA);
  WaterSurface fresh = createWaterSurface(ctx, smallSurface(n));
  test::updateSurface(ctx, fresh, heightSource(hf));
  test::SurfaceRun freshA = test::runSurface(ctx, fresh, heightSource(hf), raysA);
  CHECK(!sameBits(changedA.refractedRays, firstA.refractedRays));
  CHECK(sameBits(changedA.refractedRays, freshA.refractedRays));
  CHECK(changedA.counters.points == freshA.counters.points);
}

GPU_TEST_CASE("surface batch: dL/dweights summed over traces and pushed once equal the backwards pushed one by one") {
  const uint32_t n = 100;
  HeightField hf = createHeightField(ctx, smallField(), rng());
  std::vector<GpuRay> raysA = test::raysFromAbove(rng, n, 0.6f), raysB = test::raysFromAbove(rng, n, 0.6f);
  Buffer gradsA = createBufferFrom(ctx, rayGradients(rng, n)), gradsB = createBufferFrom(ctx, rayGradients(rng, n));

  // One by one: each trace's backward straight into the weights.
  Buffer separate = createBuffer(ctx, hf.parameterCount * 4);
  fillBuffer(ctx, separate, 0);
  {
    WaterSurface ws = createWaterSurface(ctx, smallSurface(n));
    test::updateSurface(ctx, ws, heightSource(hf));
    for (auto [rays, grads] : {std::pair{&raysA, &gradsA}, std::pair{&raysB, &gradsB}}) {
      test::SurfaceRun run = test::runSurface(ctx, ws, heightSource(hf), *rays);
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurface(cb, ws, hf, run.rays, run.records, *grads, n, separate); });
    }
  }
  const std::vector<float> reference = downloadVector<float>(ctx, separate, hf.parameterCount);

  // Summed: both traces' dL/dheight into the surface, then one push (compacted, and plain).
  for (bool compacted : {true, false}) {
    CAPTURE(compacted);
    WaterSurface ws = createWaterSurface(ctx, smallSurface(n));
    test::updateSurface(ctx, ws, heightSource(hf));
    Buffer summed = createBuffer(ctx, hf.parameterCount * 4);
    fillBuffer(ctx, summed, 0);
    for (auto [rays, grads] : {std::pair{&raysA, &gradsA}, std::pair{&raysB, &gradsB}}) {
      test::SurfaceRun run = test::runSurface(ctx, ws, heightSource(hf), *rays);
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurfaceToHeights(cb, ws, run.rays, run.records, *grads, n); });
    }
    CHECK(ws.gradientPending);
    // The heights may not change under a pending sum.
    CHECK_THROWS_WITH_AS(test::updateSurface(ctx, ws, heightSource(hf)), doctest::Contains("pending height gradient"), Error);
    if (compacted)
      pushSurfaceGradients(ctx, ws, heightSource(hf, summed));
    else
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdPushSurfaceGradients(cb, ws, heightSource(hf, summed)); });
    CHECK(!ws.gradientPending);
    std::vector<float> got = downloadVector<float>(ctx, summed, hf.parameterCount);
    double scale = 0;
    for (float g : reference) scale = std::max(scale, double(std::abs(g)));
    CHECK(scale > 1e-3);
    CHECK(relativeDifference(got, reference) < 1e-4);  // float sums in another order
  }
}
