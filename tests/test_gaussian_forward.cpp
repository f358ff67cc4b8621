// Gaussian ray tracer forward: GPU k-buffer against the brute-force double reference, both
// proxy variants, input-order and K independence, refit, water removal (camera rays).
#include <algorithm>
#include <numeric>

#include "engine/reference/camera_rays_ref.h"
#include "engine/gaussian/water_removal.h"
#include "engine/view/view_camera.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/trace/presort.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/reference/gaussian_trace_ref.h"
#include "tests/gaussian_test_scene.h"
#include "tests/gpu_test.h"

using namespace refrax;
using namespace refrax::test;

namespace {

TraceOptions randomBackground(std::mt19937& rng) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  TraceOptions o;
  for (int c = 0; c < 3; c++) o.background[c] = U(rng);
  return o;
}

void checkForwardAgainstReference(Context& ctx, std::mt19937& rng, ProxyKind kind) {
  std::uniform_int_distribution<int> count(1000, 2000);
  GaussianSet set = randomGaussians(rng, size_t(count(rng)), testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx, 16);  // below the default K: many rays need several rounds
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind);
  auto rays = raysIntoVolume(rng, 1500);
  TraceOptions opt = randomBackground(rng);
  auto gpu = traceGaussians(ctx, tracer, proxies, dev, rays, opt);
  auto cmp = compareForward(set, rays, gpu, toOptionsD(opt));
  INFO(std::string(proxyKindName(kind)) << ", " << set.count() << " Gaussians; first problem: " << cmp.firstProblem);
  INFO("worst colour rel " << cmp.worstColorRel << ", opacity " << cmp.worstOpacity << ", depth rel " << cmp.worstDepthRel
                           << ", mean hits " << cmp.meanHits << ", skipped " << cmp.skippedNearThreshold);
  CHECK(cmp.poisoned == 0);
  CHECK(cmp.compared >= rays.size() * 95 / 100);
  CHECK(cmp.meanHits > 5);  // the scene is not empty: the comparison means something
  CHECK(cmp.hitCountMismatch == 0);
  CHECK(cmp.worstColorRel <= 1e-4);
  CHECK(cmp.worstOpacity <= 1e-5);
  CHECK(cmp.worstDepthRel <= 1e-4);
  // some rays stop early (T < 1e-3) and some need several k-buffer rounds
  size_t multiRound = 0, opaque = 0;
  for (auto& r : gpu) {
    multiRound += r.rounds > 1;
    opaque += r.transmittance < 1e-3f;
  }
  CHECK(multiRound > 100);
  CHECK(opaque > 10);
  // every SH degree (the tracer reads packed coefficients and zeroes those above the degree)
  for (uint32_t degree = 0; degree < 3; degree++) {
    opt.shDegree = degree;
    auto low = traceGaussians(ctx, tracer, proxies, dev, rays, opt);
    auto c = compareForward(set, rays, low, toOptionsD(opt));
    INFO("SH degree " << degree << ": worst colour rel " << c.worstColorRel << ", first problem: " << c.firstProblem);
    CHECK(c.poisoned == 0);
    CHECK(c.compared >= rays.size() * 95 / 100);
    CHECK(c.worstColorRel <= 1e-4);
  }
}

}  // namespace

GPU_TEST_CASE("Gaussian forward matches the double reference, AABB BLAS proxies") {
  checkForwardAgainstReference(ctx, rng, ProxyKind::AabbBlas);
}

GPU_TEST_CASE("Gaussian forward matches the double reference, instanced unit-box proxies") {
  checkForwardAgainstReference(ctx, rng, ProxyKind::InstancedUnitBox);
}

GPU_TEST_CASE("Gaussian forward with a raised minimum transmittance matches the reference and stops earlier") {
  GaussianSet set = randomGaussians(rng, 1500, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  auto rays = raysIntoVolume(rng, 1500);
  TraceOptions full = randomBackground(rng), raised = full;
  raised.minTransmittance = std::uniform_real_distribution<float>(0.05f, 0.4f)(rng);
  auto gpu = traceGaussians(ctx, tracer, proxies, dev, rays, raised);
  auto cmp = compareForward(set, rays, gpu, toOptionsD(raised));
  INFO("min transmittance " << raised.minTransmittance << "; first problem: " << cmp.firstProblem);
  CHECK(cmp.poisoned == 0);
  CHECK(cmp.compared >= rays.size() * 95 / 100);
  CHECK(cmp.hitCountMismatch == 0);
  CHECK(cmp.worstColorRel <= 1e-4);
  CHECK(cmp.worstOpacity <= 1e-5);
  auto base = traceGaussians(ctx, tracer, proxies, dev, rays, full);
  size_t fewer = 0, more = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    fewer += gpu[i].hits < base[i].hits;
    more += gpu[i].hits > base[i].hits;
  }
  CHECK(more == 0);
  CHECK(fewer > 100);  // the raised threshold cut many rays short
  TraceOptions bad;
  bad.minTransmittance = 1.0f;
  CHECK_THROWS_WITH_AS(traceGaussians(ctx, tracer, proxies, dev, rays, bad), doctest::Contains("minimum transmittance"), refrax::Error);
  std::vector<float> dLoss(4 * rays.size(), 0.5f);  // the backward stops where training's forward does: the default only
  CHECK_THROWS_WITH_AS(traceGaussiansBackward(ctx, tracer, proxies, dev, rays, gpu, dLoss, raised), doctest::Contains("default minimum"),
                       refrax::Error);
}

// The depth where the opacity reaches a level (TraceOptions::depthAtOpacity, the bed's depth
// for refrax export --bottom): the t of the hit that crosses it, as the reference finds it, on
// rays through a random scene (near-ties at the level skipped by the reference's margin).
GPU_TEST_CASE("Gaussian forward: the depth at an opacity level is the crossing hit's t, as the reference's") {
  GaussianSet set = randomGaussians(rng, 300, testGaussianOptions());  // sparse enough that many rays stay under the level
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx, 16);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  auto rays = raysIntoVolume(rng, 1500);
  TraceOptions opt = randomBackground(rng);
  opt.depthAtOpacity = std::uniform_real_distribution<float>(0.3f, 0.7f)(rng);
  auto gpu = traceGaussians(ctx, tracer, proxies, dev, rays, opt);
  auto cmp = compareForward(set, rays, gpu, toOptionsD(opt));
  INFO("level " << opt.depthAtOpacity << "; worst depth rel " << cmp.worstDepthRel << ", skipped " << cmp.skippedNearThreshold
                << "; first problem: " << cmp.firstProblem);
  CHECK(cmp.poisoned == 0);
  CHECK(cmp.compared >= rays.size() * 9 / 10);
  CHECK(cmp.hitCountMismatch == 0);
  CHECK(cmp.worstDepthRel <= 1e-4);
  // the rays that reach the level carry a t inside their range; the rest 0; both kinds occur
  size_t reached = 0, unreached = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    if (gpu[i].opacity >= opt.depthAtOpacity + 1e-4f) {
      reached++;
      CHECK(gpu[i].depth >= rays[i].tmin);
      CHECK(gpu[i].depth <= rays[i].tmax);
    } else if (gpu[i].opacity < opt.depthAtOpacity - 1e-4f) {
      unreached++;
      CHECK(gpu[i].depth == 0.0f);
    }
  }
  // Both kinds occur: over 40 random scenes and levels the fewer was 122-1,378 rays of 1,500,
  // and 98 once (level 0.35) in a suite run, where a bound of 100 failed; 50 is the check.
  MESSAGE("reached " << reached << ", unreached " << unreached);
  CHECK(reached > 50);
  CHECK(unreached > 50);
  TraceOptions bad;
  bad.depthAtOpacity = 1.0f;
  CHECK_THROWS_WITH_AS(traceGaussians(ctx, tracer, proxies, dev, rays, bad), doctest::Contains("opacity level"), refrax::Error);
}

GPU_TEST_CASE("Gaussian forward: the same image for any input order, any K and either proxy") {
  GaussianSet set = randomGaussians(rng, 1200, testGaussianOptions());
  std::vector<uint32_t> perm(set.count());
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), rng);
  GaussianSet shuffled;
  for (uint32_t i : perm) shuffled.params.insert(shuffled.params.end(), set.at(i), set.at(i) + kGaussianFloats);
  auto rays = raysIntoVolume(rng, 1000);
  TraceOptions opt = randomBackground(rng);

  auto render = [&](const GaussianSet& s, uint32_t K, ProxyKind kind) {
    DeviceGaussians dev = uploadGaussians(ctx, s);
    GaussianTracer tracer = createGaussianTracer(ctx, K);
    GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, s, kind);
    return traceGaussians(ctx, tracer, proxies, dev, rays, opt);
  };
  auto base = render(set, 16, ProxyKind::AabbBlas);
  auto variants = {render(shuffled, 16, ProxyKind::AabbBlas), render(set, 1, ProxyKind::AabbBlas), render(set, 16, ProxyKind::InstancedUnitBox)};
  const char* names[] = {"shuffled input", "K = 1", "instanced proxies"};
  // Two hits whose t differ by about float rounding may blend in either order (the float t
  // values tie or flip, and a tie goes by id, which the shuffle changes): such rays, where
  // the reference's margin is below 1e-5 (TraceResultD::margin), are left out of the colour
  // check and counted. Seed 4067958454: ray 911, two of its 45 hits 1.6e-8 apart relative,
  // differs by 2.5e-4 in red.
  std::vector<double> params = ref::toDouble(set);
  ref::TraceOptionsD optD;
  for (int c = 0; c < 3; c++) optD.background[c] = opt.background[c];
  std::vector<bool> nearTie(rays.size());
  size_t nearTies = 0;
  for (size_t i = 0; i < rays.size(); i++) nearTies += nearTie[i] = ref::traceRayRef(params, ref::toRayD(rays[i]), optD).margin < 1e-5;
  CHECK(nearTies <= rays.size() / 50);
  int v = 0;
  size_t hitsTotal = 0;
  for (auto& r : base) hitsTotal += r.hits;
  CHECK(hitsTotal > rays.size() * 5);
  for (auto& other : variants) {
    double worst = 0;
    size_t hitDiff = 0;
    for (size_t i = 0; i < rays.size(); i++) {
      hitDiff += other[i].hits != base[i].hits;
      if (nearTie[i]) continue;
      for (int c = 0; c < 3; c++) worst = std::max(worst, double(std::fabs(other[i].rgb[c] - base[i].rgb[c])));
      worst = std::max(worst, double(std::fabs(other[i].opacity - base[i].opacity)));
    }
    INFO(std::string(names[v]));
    // the same hits in the same order: equal up to float summation in the SH (order of ids);
    // an ordering bug shows as ~1e-2.
    CHECK(hitDiff == 0);
    CHECK(worst <= 1e-4);
    v++;
  }
}

GPU_TEST_CASE("Gaussian proxies follow moved Gaussians by refit and by rebuild") {
  GaussianSet set = randomGaussians(rng, 1000, testGaussianOptions());
  auto rays = raysIntoVolume(rng, 800);
  std::normal_distribution<float> N(0.0f, 0.03f);
  GaussianSet moved = set;
  for (size_t i = 0; i < moved.count(); i++) {
    for (int a = 0; a < 3; a++) moved.at(i)[a] += N(rng);
    moved.at(i)[7] += N(rng);  // log scale of the first axis
  }
  for (ProxyKind kind : {ProxyKind::AabbBlas, ProxyKind::InstancedUnitBox})
    for (bool refit : {true, false}) {
      DeviceGaussians dev = uploadGaussians(ctx, set);
      GaussianTracer tracer = createGaussianTracer(ctx);
      GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind, true);
      updateGaussians(ctx, dev, moved);
      updateGaussianProxies(ctx, tracer, proxies, dev, refit);
      auto gpu = traceGaussians(ctx, tracer, proxies, dev, rays);
      auto cmp = compareForward(moved, rays, gpu, {});
      INFO(std::string(proxyKindName(kind)) << (refit ? " refit" : " rebuild") << ": " << cmp.firstProblem << " worst colour " << cmp.worstColorRel);
      CHECK(cmp.compared >= rays.size() * 95 / 100);
      CHECK(cmp.hitCountMismatch == 0);
      CHECK(cmp.worstColorRel <= 1e-4);
      auto stale = compareForward(set, rays, gpu, {});
      CHECK(stale.hitCountMismatch > 0);  // the proxies really moved
    }
}

// Training reorders the proxies every 100 steps (engine/train/train_session.cpp): made on the
// device (a GPU) or on the host (lavapipe), the new order is the moved means' median split, and
// the tree built in it traces as the reference does.
GPU_TEST_CASE("Gaussian proxies reordered after the Gaussians moved take the moved means' order, on either side") {
  GaussianSet set = randomGaussians(rng, 1000, testGaussianOptions());
  auto rays = raysIntoVolume(rng, 800);
  std::normal_distribution<float> N(0.0f, 0.05f);
  GaussianSet moved = set;
  for (size_t i = 0; i < moved.count(); i++)
    for (int a = 0; a < 3; a++) moved.at(i)[f32::kGaussMean + a] += N(rng);
  const std::vector<uint32_t> before = gaussianMeansOrder(set), after = gaussianMeansOrder(moved);
  REQUIRE(before != after);
  for (ProxyKind kind : {ProxyKind::AabbBlas, ProxyKind::InstancedUnitBox})
    for (bool onDevice : {true, false}) {
      DeviceGaussians dev = uploadGaussians(ctx, set);
      GaussianTracer tracer = createGaussianTracer(ctx);
      tracer.orderOnDevice = onDevice;
      GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind, true);
      INFO(proxyKindName(kind) << (onDevice ? ", ordered on the device" : ", ordered on the host"));
      CHECK(downloadProxyOrder(ctx, proxies) == before);
      updateGaussians(ctx, dev, moved);
      reorderGaussianProxies(ctx, tracer, proxies, dev);
      CHECK(downloadProxyOrder(ctx, proxies) == after);
      auto cmp = compareForward(moved, rays, traceGaussians(ctx, tracer, proxies, dev, rays), {});
      CHECK(cmp.compared >= rays.size() * 95 / 100);
      CHECK(cmp.hitCountMismatch == 0);
      CHECK(cmp.worstColorRel <= 1e-4);
      if (!onDevice) CHECK_THROWS_WITH(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdReorderGaussianProxies(cb, tracer, proxies, dev); }),
                                       doctest::Contains("on the host"));
    }
}

GPU_TEST_CASE("water removal: straight camera rays through the Gaussians match the reference") {
  GaussianSet set = randomGaussians(rng, 1500, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  std::uniform_real_distribution<float> U(-0.3f, 0.3f);
  FlyCamera fly;
  lookAt(fly, {U(rng), -1.5f, 1.1f}, {U(rng), U(rng), -0.4f});
  Camera cam = cameraFromFly(fly, 48, 40);
  TraceOptions opt;
  opt.background[2] = 0.25f;
  CameraRayPipelines cameraPipelines = createCameraRayPipelines(ctx);
  std::vector<GpuRay> rays;
  auto gpu = renderWithoutWater(ctx, tracer, cameraPipelines, proxies, dev, cam, opt, &rays);
  // the camera rays are the straight rays of the dataset camera (no refraction anywhere)
  double worstDir = 0;
  for (int y = 0; y < 40; y++)
    for (int x = 0; x < 48; x++) {
      ref::CameraRay want = ref::cameraRay(cam, x, y);
      const GpuRay& r = rays[size_t(y) * 48 + x];
      worstDir = std::max(worstDir, glm::length(glm::dvec3(r.dir[0], r.dir[1], r.dir[2]) - want.dir));
    }
  CHECK(worstDir < 1e-6);
  auto cmp = compareForward(set, rays, gpu, toOptionsD(opt));
  INFO(cmp.firstProblem << " worst colour " << cmp.worstColorRel);
  CHECK(cmp.poisoned == 0);
  CHECK(cmp.compared >= rays.size() * 95 / 100);
  CHECK(cmp.meanHits > 3);
  CHECK(cmp.hitCountMismatch == 0);
  CHECK(cmp.worstColorRel <= 1e-4);
}

GPU_TEST_CASE("Gaussian tracer refuses bad input with one clear error") {
  GaussianSet set = randomGaussians(rng, 10);
  DeviceGaussians dev = uploadGaussians(ctx, set);
  CHECK_THROWS_AS(createGaussianTracer(ctx, 0), Error);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas, false);
  CHECK_THROWS_AS(updateGaussianProxies(ctx, tracer, proxies, dev, true), Error);  // built without allowUpdate
  TraceOptions opt;
  opt.shDegree = 4;
  CHECK_THROWS_AS(traceGaussians(ctx, tracer, proxies, dev, raysIntoVolume(rng, 4), opt), Error);
  CHECK_THROWS_WITH_AS(proxyKindFor("boxes", ctx.caps), doctest::Contains("unknown Gaussian proxy"), Error);
  CHECK(proxyKindFor("instanced", ctx.caps) == ProxyKind::InstancedUnitBox);
  CHECK(proxyKindFor("aabb", ctx.caps) == ProxyKind::AabbBlas);
  auto badRays = raysIntoVolume(rng, 4);
  badRays[2].dir[0] = badRays[2].dir[1] = badRays[2].dir[2] = 0.0f;
  CHECK_THROWS_WITH_AS(traceGaussians(ctx, tracer, proxies, dev, badRays), doctest::Contains("zero direction"), Error);
  badRays[2].dir[2] = std::nanf("");
  CHECK_THROWS_WITH_AS(traceGaussians(ctx, tracer, proxies, dev, badRays), doctest::Contains("non-finite"), Error);
  GaussianSet bad = set;
  bad.at(3)[2] = std::nanf("");
  CHECK_THROWS_AS(validateGaussians(bad, "test"), Error);
  CHECK_THROWS_WITH_AS(uploadGaussians(ctx, bad), doctest::Contains("non-finite"), Error);
  GaussianSet zeroRotation = set;
  for (int a = 0; a < 4; a++) zeroRotation.at(1)[3 + a] = 0.0f;
  CHECK_THROWS_WITH_AS(updateGaussians(ctx, dev, zeroRotation), doctest::Contains("zero rotation"), Error);
}

TEST_CASE("the tracer's precision-matrix kernel equals the M-form kernel of the reference") {
  std::mt19937 rng(freshSeed());
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  using namespace refrax::f64;
  double worstM = 0, worstT = 0;
  for (int i = 0; i < 1000; i++) {
    real3 mu(U(rng), U(rng), U(rng)), p(3 * U(rng), 3 * U(rng), 2 + U(rng)), w(U(rng), U(rng), -1.5 + 0.5 * U(rng));
    real3 s = glm::exp(real3(-3 + U(rng), -3 + U(rng), -3 + U(rng)));
    real3x3 M = worldToLocalOf(rotationOf(real4(U(rng), U(rng), U(rng), U(rng))), real3(1) / s);
    real t1, t2;
    real3 r, x;
    real m1 = gaussianPeak(p, w, mu, M, t1, r, x);
    real m2 = gaussianPeakPrecision(p, w, 1 / dot(w, w), mu, transpose(M) * M, t2);
    worstM = std::max(worstM, std::fabs(m1 - m2) / std::max(m1, 1.0));
    worstT = std::max(worstT, std::fabs(t1 - t2) / std::max(std::fabs(t1), 1.0));
    CHECK(dot(r, r) == doctest::Approx(m1));
  }
  CHECK(worstM < 1e-9);
  CHECK(worstT < 1e-12);
}

TEST_CASE("Gaussian proxy radius is where acceptance ends, zero below alpha 1 over 255") {
  using namespace refrax::f64;
  int faint = 0, bounded = 0;
  for (int i = 0; i <= 400; i++) {
    real density = std::pow(real(10), real(-4) + real(4) * real(i) / real(400));  // 1e-4 .. 1
    if (density >= real(1)) density = real(0.999);
    real r = proxyRadiusOf(density);
    INFO("density " << density << ", radius " << r);
    if (density < kMinAlpha) {
      faint++;
      CHECK(r == real(0));
      CHECK(acceptedAlpha(real(0), density) == real(0));  // not even a ray through the mean
      continue;
    }
    bounded++;
    // just inside the radius accepted, just outside rejected: the box holds every accepted
    // peak and nothing more
    CHECK(acceptedAlpha(r * r * (real(1) - real(1e-9)), density) > real(0));
    CHECK(acceptedAlpha(r * r * (real(1) + real(1e-9)) + real(1e-12), density) == real(0));
  }
  CHECK(faint > 50);
  CHECK(bounded > 200);
}

GPU_TEST_CASE("Gaussian forward matches the double reference with faint Gaussians") {
  // Trained scenes hold many Gaussians near and below the cut-offs (density 1/255 .. 0.0113),
  // whose proxies shrink to the alpha 1/255 boundary or to a point.
  GaussianSet set = randomGaussians(rng, 1500, testGaussianOptions());
  std::uniform_real_distribution<double> faintDensity(0.002, 0.02);
  for (size_t i = 0; i < set.count(); i += 2) {
    double d = faintDensity(rng);
    set.at(i)[f32::kGaussLogitDensity] = float(std::log(d / (1 - d)));
  }
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  auto rays = raysIntoVolume(rng, 1000);
  TraceOptions opt = randomBackground(rng);
  auto gpu = traceGaussians(ctx, tracer, proxies, dev, rays, opt);
  auto cmp = compareForward(set, rays, gpu, toOptionsD(opt));
  INFO(set.count() << " Gaussians; first problem: " << cmp.firstProblem);
  INFO("worst colour rel " << cmp.worstColorRel << ", opacity " << cmp.worstOpacity << ", depth rel " << cmp.worstDepthRel
                           << ", mean hits " << cmp.meanHits << ", skipped " << cmp.skippedNearThreshold);
  CHECK(cmp.poisoned == 0);
  CHECK(cmp.compared >= rays.size() * 95 / 100);
  CHECK(cmp.meanHits > 5);
  CHECK(cmp.hitCountMismatch == 0);
  CHECK(cmp.worstColorRel <= 1e-4);
  CHECK(cmp.worstOpacity <= 1e-5);
  CHECK(cmp.worstDepthRel <= 1e-4);
}

// lavapipe builds its BVH over the primitives in the order given, splitting at the middle
// index: without the median-split presort the tree is several times slower to trace, and no
// image changes. So the order the builder receives is asserted itself.
GPU_TEST_CASE("Gaussian proxies reach the BVH builder in median-split order") {
  GaussianSet set = randomGaussians(rng, 600, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx, 16);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  // The order is the median split of the Gaussians' means (boxes of no size there), made on
  // the device (engine/trace/device_order.h).
  std::vector<Box> boxes(set.count()), means(set.count());
  for (size_t i = 0; i < set.count(); i++) {
    gaussianProxyBox(set.at(i), &boxes[i].minX);
    const float* mu = set.at(i) + f32::kGaussMean;
    means[i] = Box{mu[0], mu[1], mu[2], mu[0], mu[1], mu[2]};
  }
  const std::vector<uint32_t> expected = medianSplitOrder(means);
  REQUIRE(downloadProxyOrder(ctx, proxies) == expected);
  // Made on the other side (the host on a GPU, the device on a CPU device), the same order.
  tracer.orderOnDevice = !tracer.orderOnDevice;
  CHECK(downloadProxyOrder(ctx, buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas)) == expected);
  std::vector<uint32_t> identity(set.count());
  std::iota(identity.begin(), identity.end(), 0u);
  CHECK(expected != identity);  // random Gaussians: the split order differs from the input order
  // The AABB buffer the BLAS is built from holds slot k's box = Gaussian order[k]'s (the
  // shader's float box against the host's double one, within a margin).
  std::vector<Box> built = downloadVector<Box>(ctx, proxies.boxes, set.count());
  size_t misplaced = 0;
  for (size_t k = 0; k < set.count(); k++) {
    const Box& want = boxes[expected[k]];
    const float* a = &built[k].minX;
    const float* b = &want.minX;
    for (int c = 0; c < 6; c++) misplaced += std::abs(a[c] - b[c]) > 1e-3f * (1.0f + std::abs(b[c]));
  }
  CHECK(misplaced == 0);
}

// A Gaussian larger than any scene (log-scales of 46.1, scale 1e20, as a hand-edited PLY can
// hold) once made its box's bounds overflow the BVH build, and every ray missed every
// Gaussian, while one of scale 1e19 rendered as a fog over the scene. Its box is clamped and
// counted, and the scene renders as with the 1e19 one.
GPU_TEST_CASE("one huge Gaussian leaves the rest of the scene visible, and its clamped proxy is counted") {
  GaussianSet set = randomGaussians(rng, 400, testGaussianOptions());
  auto rays = raysIntoVolume(rng, 400);
  GaussianTracer tracer = createGaussianTracer(ctx, 16);
  auto withScale = [&](ProxyKind kind, float logScale, uint32_t* clamped) {
    GaussianSet g = set;
    for (int a = 0; a < 3; a++) g.at(7)[f32::kGaussLogScale + a] = logScale;
    g.at(7)[f32::kGaussLogitDensity] = -3.0f;  // alpha 0.05 everywhere: a light fog
    DeviceGaussians dev = uploadGaussians(ctx, g);
    GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, g, kind);
    if (clamped) *clamped = proxies.clamped;
    return traceGaussians(ctx, tracer, proxies, dev, rays, {});
  };
  for (ProxyKind kind : {ProxyKind::AabbBlas, ProxyKind::InstancedUnitBox}) {
    CAPTURE(proxyKindName(kind));
    uint32_t clamped = 0;
    auto control = withScale(kind, 43.8f, nullptr);  // scale 1e19
    auto huge = withScale(kind, 46.1f, &clamped);    // scale 1e20
    if (kind == ProxyKind::AabbBlas) CHECK(clamped == 1);
    double hitsControl = 0, hitsHuge = 0, worstOpacity = 0;
    for (size_t i = 0; i < rays.size(); i++) {
      hitsControl += control[i].hits;
      hitsHuge += huge[i].hits;
      worstOpacity = std::max(worstOpacity, double(std::abs(control[i].opacity - huge[i].opacity)));
    }
    INFO("hits per ray: scale 1e19 " << hitsControl / rays.size() << ", scale 1e20 " << hitsHuge / rays.size());
    CHECK(hitsControl > 5.0 * rays.size());
    CHECK(std::abs(hitsHuge - hitsControl) <= 0.02 * hitsControl);  // not "0.0 hits per ray"
    CHECK(worstOpacity < 1e-3);
  }
}
