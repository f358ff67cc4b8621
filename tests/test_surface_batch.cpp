// The water surface across several traces of one set of heights (engine/surface/water_surface.h):
// the lattice points stay cached until cmdUpdateSurface, and dL/dheight summed over several
// traces and pushed into the MLP once equals the traces' backwards pushed one by one.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/height/height_field_kernels.h"
#include "engine/surface/height_field_source.h"
#include "engine/vk/vk_profile.h"
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

GPU_TEST_CASE("surface batch: a host grid gradient is added on the device at the head of the next backward or push, with no submission of its own") {
  // addGridGradient (the water's priors) writes its scaled values where the device reads them;
  // the next backward or push adds them first. Started with no gradient pending, the sum
  // clears the stale grid and point gradients before the add; two calls add up.
  const uint32_t n = 100;
  HeightField hf = createHeightField(ctx, smallField(), rng());
  const std::vector<GpuRay> rays = test::raysFromAbove(rng, n, 0.6f);
  Buffer grads = createBufferFrom(ctx, rayGradients(rng, n));
  std::normal_distribution<float> N(0, 1);
  auto gridVector = [&](size_t count) {
    std::vector<float> v(count);
    for (float& x : v) x = N(rng);
    return v;
  };
  auto maxDifference = [](const std::vector<float>& a, const std::vector<double>& b) {
    double d = 0;
    for (size_t i = 0; i < a.size(); i++) d = std::max(d, std::abs(double(a[i]) - b[i]));
    return d;
  };

  // The backward's own grid gradient, alone (the reference for the sums below).
  WaterSurface alone = createWaterSurface(ctx, smallSurface(n));
  test::updateSurface(ctx, alone, heightSource(hf));
  test::SurfaceRun runAlone = test::runSurface(ctx, alone, heightSource(hf), rays);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurfaceToHeights(cb, alone, runAlone.rays, runAlone.records, grads, n); });
  const std::vector<float> backward = downloadVector<float>(ctx, alone.gridGrad, alone.gridPointCount);
  std::vector<float> backwardPoints = downloadVector<float>(ctx, alone.pointGrad, alone.cachedPoints);
  std::sort(backwardPoints.begin(), backwardPoints.end());
  const std::vector<double> sortedBackwardPoints(backwardPoints.begin(), backwardPoints.end());
  double backwardScale = 0;
  for (float g : backward) backwardScale = std::max(backwardScale, double(std::abs(g)));
  REQUIRE(backwardScale > 1e-3);

  for (bool first : {true, false}) {
    CAPTURE(first);  // the prior added before the batch's backward (a new sum), or after it
    WaterSurface ws = createWaterSurface(ctx, smallSurface(n));
    test::updateSurface(ctx, ws, heightSource(hf));
    fillBuffer(ctx, ws.gridGrad, 0x40e00000u);  // 7.0: stale values a new sum must not keep
    fillBuffer(ctx, ws.pointGrad, 0x40e00000u);
    test::SurfaceRun run = test::runSurface(ctx, ws, heightSource(hf), rays);
    const std::vector<float> a = gridVector(ws.gridPointCount), b = gridVector(ws.gridPointCount);
    auto backwardOnce = [&] {
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurfaceToHeights(cb, ws, run.rays, run.records, grads, n); });
    };
    if (!first) backwardOnce();
    GpuProfiler profiler;
    attachProfiler(ctx, profiler);
    addGridGradient(ctx, ws, a, 2.0);
    addGridGradient(ctx, ws, b, 0.5);
    const uint64_t submits = profiler.submits;
    detachProfiler(ctx);
    CHECK(submits == 0);
    CHECK(ws.gradientPending);
    if (first) backwardOnce();
    else submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdApplyAddedGradient(cb, ws); });
    CHECK(!ws.addedPending);
    std::vector<double> expected(ws.gridPointCount);
    for (size_t i = 0; i < expected.size(); i++) expected[i] = double(backward[i]) + 2.0 * double(a[i]) + 0.5 * double(b[i]);
    CHECK(maxDifference(downloadVector<float>(ctx, ws.gridGrad, ws.gridPointCount), expected) < 1e-4 * (backwardScale + 4));
    // The cached points' order is the insertion atomics' (it varies run to run): compared sorted.
    std::vector<float> points = downloadVector<float>(ctx, ws.pointGrad, ws.cachedPoints);
    REQUIRE(points.size() == sortedBackwardPoints.size());
    std::sort(points.begin(), points.end());
    CHECK(maxDifference(points, sortedBackwardPoints) < 1e-4 * backwardScale);
  }

  // The push applies it too: a prior alone, pushed, equals the backward of nothing plus it.
  WaterSurface ws = createWaterSurface(ctx, smallSurface(n));
  test::updateSurface(ctx, ws, heightSource(hf));
  fillBuffer(ctx, ws.gridGrad, 0x40e00000u);
  const std::vector<float> a = gridVector(ws.gridPointCount);
  addGridGradient(ctx, ws, a, 3.0);
  Buffer pushed = createBuffer(ctx, hf.parameterCount * 4);
  fillBuffer(ctx, pushed, 0);
  pushSurfaceGradients(ctx, ws, heightSource(hf, pushed));
  CHECK(!ws.gradientPending);
  std::vector<double> expected(ws.gridPointCount);
  for (size_t i = 0; i < expected.size(); i++) expected[i] = 3.0 * double(a[i]);
  CHECK(maxDifference(downloadVector<float>(ctx, ws.gridGrad, ws.gridPointCount), expected) < 1e-5 * 3 * 4);
  double pushedScale = 0;
  for (float g : downloadVector<float>(ctx, pushed, hf.parameterCount)) pushedScale = std::max(pushedScale, double(std::abs(g)));
  CHECK(pushedScale > 1e-3);
}

GPU_TEST_CASE("surface batch: the push runs on the count the device listed, in one submission, as the count read back") {
  // The points with a gradient are listed on the device; the height backward's chunks then take
  // their group counts from that count (height_grad_groups.comp) with `then` in the same
  // submission, where the fallback reads the count back and submits again. Both must give the
  // same weight gradient: rows past the count that a tile reads are zeroed (stale gradients
  // planted there must not count), and pass 1 writes every scratch row the tiles read (a
  // chunk of 192 points leaves partial tiles; the scratch holds the previous chunk's rows).
  const HeightFieldConfig hc = test::rippleField();
  HeightField hf = createHeightField(ctx, hc, rng());
  const uint32_t n = 1500;
  const std::vector<GpuRay> many = test::raysFromAbove(rng, n, 0.9f), few = test::raysFromAbove(rng, n / 3, 0.3f);
  Buffer gradsMany = createBufferFrom(ctx, rayGradients(rng, n)), gradsFew = createBufferFrom(ctx, rayGradients(rng, n / 3));
  const uint32_t fullChunk = hf.backwardChunk;
  for (uint32_t chunk : {fullChunk, 192u}) {
    hf.backwardChunk = chunk;
    CAPTURE(chunk);
    WaterSurface one = createWaterSurface(ctx, smallSurface(n)), readBack = createWaterSurface(ctx, smallSurface(n));
    Buffer sumOne = createBuffer(ctx, hf.parameterCount * 4), sumReadBack = createBuffer(ctx, hf.parameterCount * 4);
    Buffer marks = createBuffer(ctx, 8);
    fillBuffer(ctx, sumOne, 0);
    fillBuffer(ctx, sumReadBack, 0);
    fillBuffer(ctx, marks, 0);
    fillBuffer(ctx, one.pushGrads, 0x3f800000u);  // 1.0: stale gradients past any count
    const HeightSource queued = heightSource(hf, sumOne);
    HeightSource counted = heightSource(hf, sumReadBack);
    counted.accumulateQueued = nullptr;
    test::updateSurface(ctx, one, queued);
    test::updateSurface(ctx, readBack, counted);
    // a push of many points, then of fewer (the first push's rows lie past the second's count)
    for (auto [rays, grads] : {std::pair{&many, &gradsMany}, std::pair{&few, &gradsFew}}) {
      const uint32_t m = uint32_t(rays->size());
      for (WaterSurface* ws : {&one, &readBack}) {
        test::SurfaceRun run = test::runSurface(ctx, *ws, queued, *rays);
        submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurfaceToHeights(cb, *ws, run.rays, run.records, *grads, m); });
      }
      GpuProfiler profiler;
      attachProfiler(ctx, profiler);
      pushSurfaceGradients(ctx, one, queued, [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, marks.buffer, 0, 4, 1); });
      const uint64_t oneSubmits = profiler.submits;
      pushSurfaceGradients(ctx, readBack, counted, [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, marks.buffer, 4, 4, 1); });
      const uint64_t readBackSubmits = profiler.submits - oneSubmits;
      detachProfiler(ctx);
      CAPTURE(m);
      CHECK(oneSubmits == 1);
      CHECK(readBackSubmits == 2);
      const std::vector<uint32_t> ran = downloadVector<uint32_t>(ctx, marks, 2);
      CHECK(ran[0] == 1);
      CHECK(ran[1] == 1);
      fillBuffer(ctx, marks, 0);
      uint32_t listed = 0;
      download(ctx, one.pushCount, &listed, 4);
      CHECK(listed > (chunk == fullChunk || m < n ? 0u : 2 * chunk));  // several chunks at 192
      const std::vector<float> a = downloadVector<float>(ctx, sumOne, hf.parameterCount);
      const std::vector<float> b = downloadVector<float>(ctx, sumReadBack, hf.parameterCount);
      double scale = 0;
      for (float g : b) scale = std::max(scale, double(std::abs(g)));
      CHECK(scale > 1e-3);
      CHECK(relativeDifference(a, b) < 1e-5);  // the listed order is the atomics': float sums in another order
    }
  }
  hf.backwardChunk = fullChunk;
}

GPU_TEST_CASE("height field: the queued backward declines, recording nothing, where its table cannot hold the chunks") {
  HeightFieldConfig hc;
  hc.width = 16;
  hc.hiddenLayers = 2;
  HeightField hf = createHeightField(ctx, hc, rng());
  hf.backwardChunk = 64;
  const uint32_t perChunk = hc.hiddenLayers + 2, fits = uint32_t(hf.backwardGroups.size / 32 / perChunk) * 64;
  Buffer points = createBuffer(ctx, (fits + 64) * 8), grads = createBuffer(ctx, (fits + 64) * 4), count = createBuffer(ctx, 4);
  Buffer weights = createBuffer(ctx, hf.parameterCount * 4);
  bool small = false, large = true;
  GpuProfiler profiler;
  attachProfiler(ctx, profiler);
  profiler.gpu = false;  // counts dispatches only (hundreds of chunks would outrun the timer's slots)
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    vkCmdFillBuffer(cb, count.buffer, 0, 4, 0);
    vkCmdFillBuffer(cb, weights.buffer, 0, VK_WHOLE_SIZE, 0);
    cmdBarrier(cb);
    small = cmdAccumulateHeightGradientsQueued(cb, hf, points, grads, count, fits, weights);
    const uint64_t before = profiler.dispatches;
    large = cmdAccumulateHeightGradientsQueued(cb, hf, points, grads, count, fits + 64, weights);
    CHECK(profiler.dispatches == before);
  });
  detachProfiler(ctx);
  CHECK(small);
  CHECK_FALSE(large);
  const std::vector<float> w = downloadVector<float>(ctx, weights, hf.parameterCount);
  CHECK(std::all_of(w.begin(), w.end(), [](float x) { return x == 0.0f; }));  // a count of 0 adds nothing
}
