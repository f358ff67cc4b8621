// The tiled Gaussian forward (engine/gaussian/tiled_trace.h): the bundle cone's sphere test against
// brute force in float and double, and the tiled forward against the BVH forward and the
// double reference on camera rays, refracted rays with empty ones among them, several k-buffer
// rounds, and lists that overflow.
#include <algorithm>
#include <cmath>

#include "engine/view/fly_camera.h"
#include "engine/view/view_camera.h"
#include "engine/reference/camera_rays_ref.h"
#include "engine/base/shared_math.h"
#include "engine/surface/surface_math.h"
#include "engine/gaussian/tiled_trace.h"
#include "engine/vk/vk_commands.h"
#include "engine/gaussian/water_removal.h"
#include "tests/gaussian_test_scene.h"
#include "tests/gpu_test.h"

namespace refrax::f32 {
#include "ray_bundle.glsl"
}
namespace refrax::f64 {
#include "ray_bundle.glsl"
}

using namespace refrax;
using namespace refrax::test;

namespace {

struct BundleRay {
  glm::dvec3 o, d;  // unit d
  double sMin, sMax;
};

// The cone of a bundle as tile_cull.comp builds it: mean origin, normalised mean direction,
// the largest deviations, the union of the ranges.
struct Cone {
  glm::dvec3 origin{0.0}, dir{0.0};
  double originRadius = 0, dirRadius = 0, sMin = 1e300, sMax = 0;
};
Cone coneOf(const std::vector<BundleRay>& rays) {
  Cone c;
  for (auto& r : rays) {
    c.origin += r.o / double(rays.size());
    c.dir += r.d;
  }
  c.dir = glm::normalize(c.dir);
  for (auto& r : rays) {
    c.originRadius = std::max(c.originRadius, glm::length(r.o - c.origin));
    c.dirRadius = std::max(c.dirRadius, glm::length(r.d - c.dir));
    c.sMin = std::min(c.sMin, r.sMin);
    c.sMax = std::max(c.sMax, r.sMax);
  }
  return c;
}

// Distance from p to the segment o + s d, s in [sMin, sMax] (unit d).
double segmentDistance(const BundleRay& r, const glm::dvec3& p) {
  double s = std::clamp(glm::dot(p - r.o, r.d), r.sMin, r.sMax);
  return glm::length(r.o + s * r.d - p);
}

}  // namespace

TEST_CASE("ray bundle cone: never culls a sphere a member ray reaches, culls most far ones (float and double)") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0), U01(0.0, 1.0);
  size_t reached = 0, missed = 0, culled32 = 0, culled64 = 0, wrongly32 = 0, wrongly64 = 0;
  for (int bundle = 0; bundle < 200; bundle++) {
    // an 8x8 tile's rays: origins in a blob (0 for camera rays), directions within a cone
    // whose width ranges from a pixel's to wide-angle, ranges that start at 0 or beyond
    double spread = bundle % 4 == 0 ? 0.0 : 0.05 * U01(rng);
    double angle = std::pow(10.0, -3.0 + 3.0 * U01(rng));  // 1e-3 .. 1 rad
    glm::dvec3 axis = glm::normalize(glm::dvec3(U(rng), U(rng), -2.0));
    glm::dvec3 base(U(rng), U(rng), 1.0 + U01(rng));
    std::vector<BundleRay> rays;
    for (int k = 0; k < 64; k++) {
      BundleRay r;
      r.o = base + spread * glm::dvec3(U(rng), U(rng), U(rng));
      r.d = glm::normalize(axis + angle * glm::dvec3(U(rng), U(rng), U(rng)));
      r.sMin = bundle % 3 == 0 ? 0.0 : 0.5 * U01(rng);
      r.sMax = r.sMin + (bundle % 5 == 0 ? 100.0 : 3.0 * U01(rng));
      rays.push_back(r);
    }
    Cone c = coneOf(rays);
    f32::real3 o32(c.origin), d32(c.dir);
    for (int q = 0; q < 100; q++) {
      // spheres around where the bundle goes, some on it and most beside it
      glm::dvec3 centre = base + (0.2 + 2.5 * U01(rng)) * axis + 0.3 * glm::dvec3(U(rng), U(rng), U(rng));
      double radius = 0.002 + 0.08 * U01(rng);
      double nearest = 1e300;
      for (auto& r : rays) nearest = std::min(nearest, segmentDistance(r, centre));
      bool reach64 = f64::bundleMayReachSphere(c.origin, c.dir, c.originRadius, c.dirRadius, c.sMin, c.sMax, centre, radius);
      bool reach32 = f32::bundleMayReachSphere(o32, d32, float(c.originRadius), float(c.dirRadius), float(c.sMin), float(c.sMax),
                                               f32::real3(centre), float(radius));
      if (nearest <= radius) {
        reached++;
        wrongly64 += !reach64;
        wrongly32 += !reach32;
      } else {
        missed++;
        culled64 += !reach64;
        culled32 += !reach32;
      }
    }
  }
  INFO(reached << " spheres reached, " << missed << " missed; culled " << culled64 << " (double) " << culled32 << " (float)");
  CHECK(reached > 1000);  // both kinds occur often enough to mean something
  CHECK(missed > 5000);
  CHECK(wrongly64 == 0);
  CHECK(wrongly32 == 0);
  CHECK(culled64 > missed / 2);  // thin bundles cull most of what they miss
  CHECK(culled32 > missed / 2);
}

TEST_CASE("ray bundle cone: a thin cone culls exactly what lies outside it") {
  // a single ray (radii 0) along +z from the origin, s in [1, 2]: a sphere of radius 0.1
  // reaches it only within 0.1 of the segment
  glm::dvec3 o(0.0), d(0.0, 0.0, 1.0);
  CHECK(f64::bundleMayReachSphere(o, d, 0.0, 0.0, 1.0, 2.0, glm::dvec3(0.09, 0.0, 1.5), 0.1));
  CHECK_FALSE(f64::bundleMayReachSphere(o, d, 0.0, 0.0, 1.0, 2.0, glm::dvec3(0.11, 0.0, 1.5), 0.1));
  CHECK_FALSE(f64::bundleMayReachSphere(o, d, 0.0, 0.0, 1.0, 2.0, glm::dvec3(0.0, 0.0, 2.11), 0.1));  // beyond sMax
  CHECK_FALSE(f64::bundleMayReachSphere(o, d, 0.0, 0.0, 1.0, 2.0, glm::dvec3(0.0, 0.0, 0.89), 0.1));  // before sMin
  // the cone widens by dirRadius per unit: at s = 2 its radius is 0.2 + originRadius 0.05
  CHECK(f64::bundleMayReachSphere(o, d, 0.05, 0.1, 1.0, 2.0, glm::dvec3(0.34, 0.0, 2.0), 0.1));
  CHECK_FALSE(f64::bundleMayReachSphere(o, d, 0.05, 0.1, 1.0, 2.0, glm::dvec3(0.36, 0.0, 2.0), 0.1));
  // a cone at 90 degrees or more culls nothing
  CHECK(f64::bundleMayReachSphere(o, d, 0.0, 1.0, 1.0, 2.0, glm::dvec3(0.0, 0.0, -5.0), 0.1));
}

namespace {

// Camera rays of a width x height image looking down into the test volume.
std::vector<GpuRay> cameraImage(std::mt19937& rng, int width, int height) {
  std::uniform_real_distribution<float> U(-0.3f, 0.3f);
  FlyCamera fly;
  lookAt(fly, {U(rng), -1.2f, 1.0f}, {U(rng), U(rng), -0.5f});
  Camera cam = cameraFromFly(fly, width, height);
  std::vector<GpuRay> rays;
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) {
      ref::CameraRay c = ref::cameraRay(cam, x, y);
      rays.push_back({{float(c.origin.x), float(c.origin.y), float(c.origin.z)}, 0.0f,
                      {float(c.dir.x), float(c.dir.y), float(c.dir.z)}, 100.0f});
    }
  return rays;
}

// The same rays refracted at a wavy water plane z = 0.15 + 0.02 sin(..) as the surface stage
// hands them on: origin at the hit, unit refracted direction, tmin 0; rays that miss the
// water's square continue unchanged and a stripe of rays is empty (tmin = tmax = 0).
std::vector<GpuRay> refractedImage(const std::vector<GpuRay>& camera, int width) {
  std::vector<GpuRay> out = camera;
  for (size_t i = 0; i < camera.size(); i++) {
    const GpuRay& r = camera[i];
    glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d = glm::normalize(glm::dvec3(r.dir[0], r.dir[1], r.dir[2]));
    double t = (0.15 - o.z) / d.z;
    glm::dvec3 p = o + t * d;
    if (std::abs(p.x) > 0.45 || std::abs(p.y) > 0.45) continue;  // off the water
    if (int(i % size_t(width)) % 11 == 5) {                       // an empty column (invalid camera rays become these)
      out[i] = {{0, 0, 0}, 0.0f, {0, 0, -1}, 0.0f};
      continue;
    }
    p.z += 0.02 * std::sin(9.0 * p.x + 4.0 * p.y);
    glm::dvec3 n = glm::normalize(glm::dvec3(-0.18 * std::cos(9.0 * p.x + 4.0 * p.y), -0.08 * std::cos(9.0 * p.x + 4.0 * p.y), 1.0));
    glm::dvec3 w = f64::snellRefract(d, f64::snellFacingSign(d, n) * n, 1.0 / 1.33);
    out[i] = {{float(p.x), float(p.y), float(p.z)}, 0.0f, {float(w.x), float(w.y), float(w.z)}, 50.0f};
  }
  return out;
}

void checkSameAsBvh(const std::vector<GpuTraceResult>& tiled, const std::vector<GpuTraceResult>& bvh) {
  size_t hitMismatch = 0;
  double worst = 0;
  for (size_t i = 0; i < bvh.size(); i++) {
    hitMismatch += tiled[i].hits != bvh[i].hits || tiled[i].rounds != bvh[i].rounds;
    for (int c = 0; c < 3; c++) worst = std::max(worst, double(std::fabs(tiled[i].rgb[c] - bvh[i].rgb[c])));
    worst = std::max(worst, double(std::fabs(tiled[i].opacity - bvh[i].opacity)));
    worst = std::max(worst, double(std::fabs(tiled[i].depth - bvh[i].depth)) / std::max(1.0, double(std::fabs(bvh[i].depth))));
  }
  INFO("rays with other hits or rounds: " << hitMismatch << ", worst difference " << worst);
  CHECK(hitMismatch == 0);
  CHECK(worst <= 1e-5);
}

}  // namespace

GPU_TEST_CASE("tiled forward equals the BVH forward and the double reference (camera and refracted rays, both proxies)") {
  GaussianSet set = randomGaussians(rng, 1500, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  const int width = 45, height = 37;  // not multiples of the tile: partial tiles at two edges
  std::vector<GpuRay> camera = cameraImage(rng, width, height);
  std::vector<GpuRay> refracted = refractedImage(camera, width);
  for (ProxyKind kind : {ProxyKind::AabbBlas, ProxyKind::InstancedUnitBox})
    for (uint32_t K : {16u, 48u}) {
      GaussianTracer tracer = createGaussianTracer(ctx, K);
      GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind);
      for (const auto* rays : {&camera, &refracted}) {
        CAPTURE(proxyKindName(kind));
        CAPTURE(K);
        bool isCamera = rays == &camera;
        CAPTURE(isCamera);
        TraceOptions opt;
        opt.background[1] = 0.3f;
        TileStats stats;
        auto tiled = traceGaussiansTiled(ctx, tracer, proxies, *rays, width, height, opt, kDefaultTileCapacity, &stats);
        auto bvh = traceGaussians(ctx, tracer, proxies, dev, *rays, opt);
        checkSameAsBvh(tiled, bvh);
        auto cmp = compareForward(set, *rays, tiled, toOptionsD(opt));
        INFO(cmp.firstProblem << "; mean candidates per tile " << stats.meanListed << " of " << set.count());
        CHECK(cmp.poisoned == 0);
        CHECK(cmp.compared >= rays->size() * 95 / 100);
        CHECK(cmp.meanHits > 3);
        CHECK(cmp.hitCountMismatch == 0);
        CHECK(cmp.worstColorRel <= 1e-4);
        CHECK(stats.overflowed == 0);
        // the lists are what makes it fast: each tile lists a part of the scene (a large part
        // here, where a tile spans 10 degrees of view; 1/8 of that at 256x256). Over seeds
        // 1-120 camera tiles listed 0.107-0.117 of the Gaussians and refracted ones 0.24-0.54
        // (the spread is the random camera's view of the waves), so the bars sit well above.
        CHECK(stats.meanListed < (isCamera ? 0.25 : 0.75) * double(set.count()));
        size_t multiRound = 0;
        for (auto& r : tiled) multiRound += r.rounds > 1;
        if (K == 16) CHECK(multiRound > 50);  // the k-buffer restarts from the list too
      }
    }
}

GPU_TEST_CASE("tiled forward: tiles or blocks whose list overflows traverse the BVH or test every Gaussian, and give the same image") {
  GaussianSet set = randomGaussians(rng, 1200, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  const int width = 72, height = 40;  // 3x2 blocks (two of them partial) of 9x5 tiles
  std::vector<GpuRay> rays = cameraImage(rng, width, height);
  TraceOptions opt;
  TileStats full;
  auto reference = traceGaussiansTiled(ctx, tracer, proxies, rays, width, height, opt, kDefaultTileCapacity, &full);
  CHECK(full.overflowed == 0);
  CHECK(full.blocksOverflowed == 0);
  checkSameAsBvh(reference, traceGaussians(ctx, tracer, proxies, dev, rays, opt));
  // a tile capacity near the mean list: some tiles overflow, some do not; a capacity a quarter
  // of a block's mean list (the block's capacity is 4x the tile's): the blocks overflow too
  uint32_t tileCase = std::max(1u, uint32_t(full.meanListed)), blockCase = std::max(1u, uint32_t(full.meanBlockListed / 16));
  for (uint32_t capacity : {tileCase, blockCase}) {
    TileStats small;
    auto overflowing = traceGaussiansTiled(ctx, tracer, proxies, rays, width, height, opt, capacity, &small);
    INFO("capacity " << capacity << ": tile lists mean " << full.meanListed << ", max " << full.maxListed << "; block lists mean "
                     << full.meanBlockListed << "; tiles over " << small.overflowed << ", blocks over " << small.blocksOverflowed);
    CHECK(small.overflowed > 0);
    if (capacity == tileCase) CHECK(small.overflowed < small.tiles);
    if (capacity == blockCase) CHECK(small.blocksOverflowed > 0);
    checkSameAsBvh(overflowing, reference);
  }
}

GPU_TEST_CASE("tiled forward: tile lists reshaped for a smaller image give that image's result") {
  GaussianSet set = randomGaussians(rng, 800, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  TileCandidates tiles = createTileCandidates(ctx, 70, 45);
  CHECK_FALSE(reshapeTileCandidates(tiles, 140, 45));  // more tiles than the buffers hold
  CHECK(tiles.width == 70);
  const uint32_t width = 37, height = 29;  // 5x4 tiles, 2x1 blocks: other strides than 70x45's
  REQUIRE(reshapeTileCandidates(tiles, width, height));
  CHECK(tiles.tilesX == 5);
  CHECK(tiles.blocksX == 2);
  std::vector<GpuRay> rays = cameraImage(rng, int(width), int(height));
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer results = createBuffer(ctx, rays.size() * sizeof(GpuTraceResult));
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdCullTiles(cb, tracer, proxies, rayBuf, tiles);
    cmdBarrier(cb);
    cmdTraceForwardTiled(cb, tracer, proxies, rayBuf, results, tiles);
  });
  checkSameAsBvh(downloadVector<GpuTraceResult>(ctx, results, rays.size()), traceGaussians(ctx, tracer, proxies, dev, rays));
}

GPU_TEST_CASE("tiled forward refuses rays that are not the stated image, and empty images") {
  GaussianSet set = randomGaussians(rng, 20);
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  std::vector<GpuRay> rays = cameraImage(rng, 8, 4);
  CHECK_THROWS_WITH_AS(traceGaussiansTiled(ctx, tracer, proxies, rays, 8, 5), doctest::Contains("are not a 8x5 image"), Error);
  CHECK_THROWS_WITH_AS(createTileCandidates(ctx, 0, 4), doctest::Contains("no pixels"), Error);
  CHECK_THROWS_WITH_AS(createTileCandidates(ctx, 8, 4, 0), doctest::Contains("at least one candidate"), Error);
  rays[3].dir[0] = NAN;
  CHECK_THROWS_WITH_AS(traceGaussiansTiled(ctx, tracer, proxies, rays, 8, 4), doctest::Contains("non-finite"), Error);
}
