// Gaussian ray tracer backward: the double reference's analytic gradient against central
// differences of the reference forward, and the GPU backward (float atomicAdd and the
// compare-and-swap fallback, both proxy variants) against the reference's gradient.
//
// Error measure for a parameter group (mean, rotation, log scale, logit density, SH, ray
// origin, ray direction): max |got - expected| / max |expected| over every entry of the
// group (all Gaussians or all rays), so one badly scaled entry cannot hide and tiny entries
// are not judged by their own size.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "tests/gaussian_test_scene.h"
#include "tests/gpu_test.h"

using namespace refrax;
using namespace refrax::test;

namespace {

struct Group {
  const char* name;
  uint32_t first, count;
};
const Group kGroups[] = {{"mean", f32::kGaussMean, 3},
                         {"rotation", f32::kGaussRotation, 4},
                         {"log scale", f32::kGaussLogScale, 3},
                         {"logit density", f32::kGaussLogitDensity, 1},
                         {"SH", f32::kGaussSH, 48}};

struct GroupError {
  double worstDiff = 0, largest = 0;
  double rel() const { return largest > 0 ? worstDiff / largest : (worstDiff > 0 ? 1e300 : 0); }
};

template <typename GotFn, typename WantFn>
GroupError groupError(size_t gaussians, const Group& g, GotFn got, WantFn want) {
  GroupError e;
  for (size_t i = 0; i < gaussians; i++)
    for (uint32_t k = g.first; k < g.first + g.count; k++) {
      size_t idx = i * kGaussianFloats + k;
      e.worstDiff = std::max(e.worstDiff, std::fabs(double(got(idx)) - want(idx)));
      e.largest = std::max(e.largest, std::fabs(want(idx)));
    }
  return e;
}

// Rays whose reference result is at least `margin` away from every discontinuity.
std::vector<GpuRay> unambiguousRays(std::mt19937& rng, const std::vector<double>& params, size_t n, double margin,
                                    const ref::TraceOptionsD& opt) {
  std::vector<GpuRay> out;
  for (int attempt = 0; attempt < 20 && out.size() < n; attempt++)
    for (const GpuRay& r : raysIntoVolume(rng, n))
      if (out.size() < n && ref::traceRayRef(params, ref::toRayD(r), opt).margin >= margin) out.push_back(r);
  return out;
}

double lossOf(const std::vector<double>& params, const std::vector<ref::RayD>& rays, const std::vector<double>& dLoss,
              const ref::TraceOptionsD& opt) {
  double L = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    ref::TraceResultD r = ref::traceRayRef(params, rays[i], opt);
    L += dLoss[4 * i] * r.rgb[0] + dLoss[4 * i + 1] * r.rgb[1] + dLoss[4 * i + 2] * r.rgb[2] + dLoss[4 * i + 3] * r.opacity;
  }
  return L;
}

}  // namespace

TEST_CASE("Gaussian tracer reference: analytic gradient matches central differences") {
  std::mt19937 rng(freshSeed());
  MESSAGE("seed replay: REFRAX_TEST_SEED");
  RandomGaussianOptions go = testGaussianOptions();
  go.lo[0] = go.lo[1] = -0.15f, go.hi[0] = go.hi[1] = 0.15f;  // a small dense volume: many hits per ray
  go.lo[2] = -0.3f;
  go.sigmaMin = 0.03f, go.sigmaMax = 0.07f;
  GaussianSet set = randomGaussians(rng, 60, go);
  std::vector<double> params = ref::toDouble(set);
  ref::TraceOptionsD opt;
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int c = 0; c < 3; c++) opt.background[c] = 0.5 + 0.5 * U(rng);
  std::vector<ref::RayD> rays;
  for (int attempt = 0; attempt < 200 && rays.size() < 6; attempt++) {
    auto r = ref::randomRays(rng, 1, {{-0.2f, -0.2f, 0.6f}, {0.2f, 0.2f, 1.0f}, {-0.1f, -0.1f, -0.3f}, {0.1f, 0.1f, 0.0f}}, 100.0f);
    ref::RayD rd = ref::toRayD(r[0]);
    ref::TraceResultD res = ref::traceRayRef(params, rd, opt);
    if (res.margin >= 1e-3 && res.hits >= 3) rays.push_back(rd);
  }
  REQUIRE(rays.size() == 6);
  std::vector<double> dLoss(4 * rays.size());
  for (double& v : dLoss) v = U(rng);

  std::vector<double> analytic(params.size(), 0.0);
  std::vector<ref::RayGradD> rayGrads;
  for (size_t i = 0; i < rays.size(); i++) rayGrads.push_back(ref::traceRayBackwardRef(params, rays[i], &dLoss[4 * i], analytic, opt));

  const double h = 1e-6;
  std::vector<double> numeric(params.size(), 0.0);
  for (size_t k = 0; k < params.size(); k++) {
    std::vector<double> p = params;
    p[k] = params[k] + h;
    double up = lossOf(p, rays, dLoss, opt);
    p[k] = params[k] - h;
    numeric[k] = (up - lossOf(p, rays, dLoss, opt)) / (2 * h);
  }
  for (const Group& g : kGroups) {
    GroupError e = groupError(set.count(), g, [&](size_t i) { return analytic[i]; }, [&](size_t i) { return numeric[i]; });
    INFO(std::string(g.name) << ": worst diff " << e.worstDiff << ", largest " << e.largest);
    CHECK(e.largest > 1e-4);  // the group really has a gradient
    CHECK(e.rel() <= 1e-3);
  }
  // ray origin and direction, per ray through its own loss term
  GroupError eo, ed;
  for (size_t i = 0; i < rays.size(); i++)
    for (int a = 0; a < 6; a++) {
      ref::RayD up = rays[i], down = rays[i];
      double* u = a < 3 ? &up.origin[a] : &up.dir[a - 3];
      double* d = a < 3 ? &down.origin[a] : &down.dir[a - 3];
      *u += h;
      *d -= h;
      double fd = (lossOf(params, {up}, {dLoss.begin() + 4 * i, dLoss.begin() + 4 * i + 4}, opt) -
                   lossOf(params, {down}, {dLoss.begin() + 4 * i, dLoss.begin() + 4 * i + 4}, opt)) /
                  (2 * h);
      double an = a < 3 ? rayGrads[i].dOrigin[a] : rayGrads[i].dDir[a - 3];
      GroupError& e = a < 3 ? eo : ed;
      e.worstDiff = std::max(e.worstDiff, std::fabs(an - fd));
      e.largest = std::max(e.largest, std::fabs(fd));
    }
  INFO("origin: worst diff " << eo.worstDiff << " largest " << eo.largest << "; direction: " << ed.worstDiff << " / " << ed.largest);
  CHECK(eo.largest > 1e-3);
  CHECK(ed.largest > 1e-3);
  CHECK(eo.rel() <= 1e-3);
  CHECK(ed.rel() <= 1e-3);
}

namespace {

void checkGradients(const GaussianSet& set, const GaussianGradients& gpu, const std::vector<double>& want, const std::vector<double>& stats,
                    const std::vector<ref::RayGradD>& wantRays, ProxyKind kind, bool cas, bool viewpoint, uint32_t shDegree);

void checkBackwardAgainstReference(Context& ctx, std::mt19937& rng, ProxyKind kind, bool cas, bool viewpoint, uint32_t shDegree) {
  GaussianSet set = randomGaussians(rng, 1000, testGaussianOptions());
  std::vector<double> params = ref::toDouble(set);
  TraceOptions opt;
  opt.shDegree = shDegree;
  std::uniform_real_distribution<float> U(-1.0f, 1.0f);
  for (int c = 0; c < 3; c++) opt.background[c] = 0.5f + 0.5f * U(rng);
  // Statistics measured from a viewpoint behind the rays' origins (as for refracted rays), or from the origins.
  if (viewpoint) opt.statisticsViewpoint = glm::vec3(U(rng), U(rng), 3.0f + U(rng));
  ref::TraceOptionsD optD = toOptionsD(opt);
  auto rays = unambiguousRays(rng, params, 600, 1e-4, optD);
  REQUIRE(rays.size() == 600);
  std::vector<float> dLoss(4 * rays.size());
  for (float& v : dLoss) v = U(rng);
  // every 7th ray a masked pixel: no loss gradient, so it adds nothing and counts in no statistic
  for (size_t i = 0; i < rays.size(); i += 7) std::fill(dLoss.begin() + 4 * i, dLoss.begin() + 4 * i + 4, 0.0f);

  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx, 16, cas);
  REQUIRE(tracer.casAtomics == (cas || !ctx.caps.floatAtomicAdd));
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind);
  auto fwd = traceGaussians(ctx, tracer, proxies, dev, rays, opt);

  std::vector<double> want(params.size(), 0.0), stats(2 * set.count(), 0.0);
  std::vector<ref::RayGradD> wantRays;
  for (size_t i = 0; i < rays.size(); i++) {
    double dl[4] = {dLoss[4 * i], dLoss[4 * i + 1], dLoss[4 * i + 2], dLoss[4 * i + 3]};
    wantRays.push_back(ref::traceRayBackwardRef(params, ref::toRayD(rays[i]), dl, want, optD, &stats));
  }
  // The backward re-tracing every ray, reading hit records that hold every ray's hits, and
  // reading records that hold only some rays' hits (the others re-traced).
  std::vector<uint32_t> hits;
  for (const GpuTraceResult& r : fwd) hits.push_back(r.hits);
  std::sort(hits.begin(), hits.end());
  const uint32_t median = hits[hits.size() / 2], most = hits.back();
  REQUIRE(median >= 2);
  REQUIRE(median < most);  // some rays fit `median` records, some do not
  for (uint32_t perRay : {0u, most, median}) {
    INFO("hit records per ray: " << perRay << " (0: re-traced; most hits on a ray " << most << ")");
    GaussianGradients gpu = traceGaussiansBackward(ctx, tracer, proxies, dev, rays, fwd, dLoss, opt, perRay);
    checkGradients(set, gpu, want, stats, wantRays, kind, cas, viewpoint, shDegree);
  }
}

void checkGradients(const GaussianSet& set, const GaussianGradients& gpu, const std::vector<double>& want, const std::vector<double>& stats,
                    const std::vector<ref::RayGradD>& wantRays, ProxyKind kind, bool cas, bool viewpoint, uint32_t shDegree) {
  const size_t nrays = wantRays.size();
  size_t nan = 0;
  for (float v : gpu.params) nan += std::isnan(v);
  for (auto& r : gpu.rays)
    for (int a = 0; a < 3; a++) nan += std::isnan(r.dOrigin[a]) + std::isnan(r.dDir[a]);
  CHECK(nan == 0);
  INFO(std::string(proxyKindName(kind)) << (cas ? ", compare-and-swap atomics" : ", float atomicAdd") << (viewpoint ? ", statistics from a viewpoint" : "")
                                        << ", SH degree " << shDegree);
  for (const Group& g : kGroups) {
    GroupError e = groupError(set.count(), g, [&](size_t i) { return gpu.params[i]; }, [&](size_t i) { return want[i]; });
    INFO(std::string(g.name) << ": worst diff " << e.worstDiff << ", largest " << e.largest);
    CHECK(e.largest > 1e-3);
    CHECK(e.rel() <= 1e-3);
  }
  GroupError eo, ed;
  for (size_t i = 0; i < nrays; i++)
    for (int a = 0; a < 3; a++) {
      eo.worstDiff = std::max(eo.worstDiff, std::fabs(double(gpu.rays[i].dOrigin[a]) - wantRays[i].dOrigin[a]));
      eo.largest = std::max(eo.largest, std::fabs(wantRays[i].dOrigin[a]));
      ed.worstDiff = std::max(ed.worstDiff, std::fabs(double(gpu.rays[i].dDir[a]) - wantRays[i].dDir[a]));
      ed.largest = std::max(ed.largest, std::fabs(wantRays[i].dDir[a]));
    }
  INFO("ray origin " << eo.worstDiff << " / " << eo.largest << ", direction " << ed.worstDiff << " / " << ed.largest);
  CHECK(eo.rel() <= 1e-3);
  CHECK(ed.rel() <= 1e-3);
  // densification statistics: exact hit counts, position-gradient norms like the gradients
  size_t countDiff = 0;
  GroupError en;
  for (size_t i = 0; i < set.count(); i++) {
    countDiff += gpu.stats[2 * i + 1] != float(stats[2 * i + 1]);
    en.worstDiff = std::max(en.worstDiff, std::fabs(gpu.stats[2 * i] - stats[2 * i]));
    en.largest = std::max(en.largest, std::fabs(stats[2 * i]));
  }
  CHECK(countDiff == 0);
  CHECK(en.largest > 0);
  CHECK(en.rel() <= 1e-3);
}

}  // namespace

GPU_TEST_CASE("Gaussian backward matches the reference: AABB BLAS, float atomics") {
  checkBackwardAgainstReference(ctx, rng, ProxyKind::AabbBlas, false, true, 3);
}
GPU_TEST_CASE("Gaussian backward matches the reference: instanced proxies, float atomics") {
  checkBackwardAgainstReference(ctx, rng, ProxyKind::InstancedUnitBox, false, false, 1);
}
GPU_TEST_CASE("Gaussian backward matches the reference: AABB BLAS, compare-and-swap atomics") {
  checkBackwardAgainstReference(ctx, rng, ProxyKind::AabbBlas, true, false, 2);
}
GPU_TEST_CASE("Gaussian backward matches the reference: instanced proxies, compare-and-swap atomics") {
  checkBackwardAgainstReference(ctx, rng, ProxyKind::InstancedUnitBox, true, true, 0);
}

GPU_TEST_CASE("Gaussian backward refuses a non-finite loss gradient") {
  GaussianSet set = randomGaussians(rng, 50, testGaussianOptions());
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianTracer tracer = createGaussianTracer(ctx);
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, ProxyKind::AabbBlas);
  auto rays = raysIntoVolume(rng, 8);
  auto fwd = traceGaussians(ctx, tracer, proxies, dev, rays);
  std::vector<float> dLoss(4 * rays.size(), 0.5f);
  dLoss[5] = std::nanf("");
  CHECK_THROWS_WITH_AS(traceGaussiansBackward(ctx, tracer, proxies, dev, rays, fwd, dLoss), doctest::Contains("non-finite"), Error);
}
