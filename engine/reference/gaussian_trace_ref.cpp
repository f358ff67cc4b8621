#include "engine/reference/gaussian_trace_ref.h"

#include <algorithm>
#include <cmath>

#include "engine/gaussian/gaussian_math.h"

namespace refrax::ref {

using namespace refrax::f64;

namespace {

struct HitD {
  double t;
  uint32_t id;
  double rawAlpha;
};

struct GaussianD {
  real3 mu;
  real4 q;
  real3 invScale;
  real density;
  real3x3 R, M;
};

GaussianD gaussianAt(const std::vector<double>& p, uint32_t id) {
  const double* g = p.data() + size_t(id) * kGaussFloats;
  GaussianD G;
  G.mu = real3(g[kGaussMean], g[kGaussMean + 1], g[kGaussMean + 2]);
  G.q = real4(g[kGaussRotation], g[kGaussRotation + 1], g[kGaussRotation + 2], g[kGaussRotation + 3]);
  G.invScale = glm::exp(-real3(g[kGaussLogScale], g[kGaussLogScale + 1], g[kGaussLogScale + 2]));
  G.density = sigmoidOf(g[kGaussLogitDensity]);
  G.R = rotationOf(G.q);
  G.M = worldToLocalOf(G.R, G.invScale);
  return G;
}

double relDist(double a, double b) { return std::fabs(a - b) / std::max(std::fabs(b), 1e-30); }

// Every accepted hit of the ray, sorted by (t, id); margin updated for acceptance.
std::vector<HitD> collectHits(const std::vector<double>& p, const real3& o, const real3& d, double tmin, double tmax, double& margin) {
  std::vector<HitD> hits;
  uint32_t n = uint32_t(p.size() / kGaussFloats);
  for (uint32_t id = 0; id < n; id++) {
    GaussianD G = gaussianAt(p, id);
    real t;
    real3 r, x;
    real m = gaussianPeak(o, d, G.mu, G.M, t, r, x);
    real a = G.density * exp(-0.5 * m);
    if (a > 1e-6) {  // only near-threshold values matter to the margin
      margin = std::min({margin, relDist(a, std::min(kMinKernelResponse, 0.97 * G.density)), relDist(a, kMinAlpha)});
    }
    real accepted = acceptedAlpha(m, G.density);
    if (accepted == 0) continue;
    margin = std::min({margin, relDist(accepted, kMaxAlpha), std::fabs(t - tmin) / (1 + std::fabs(tmin)),
                       std::fabs(t - tmax) / (1 + std::fabs(tmax))});
    if (t <= tmin || t >= tmax) continue;
    hits.push_back({t, id, accepted});
  }
  std::sort(hits.begin(), hits.end(), [](const HitD& a, const HitD& b) { return a.t < b.t || (a.t == b.t && a.id < b.id); });
  // Two hits' order flips only when their t differ by about the float rounding of t
  // (~1e-7 relative), far less than alphas near a threshold can move: scaled to match.
  for (size_t k = 1; k < hits.size(); k++) margin = std::min(margin, 100 * std::fabs(hits[k].t - hits[k - 1].t) / (1 + std::fabs(hits[k].t)));
  return hits;
}

real3 shColorRaw(const std::vector<double>& p, uint32_t id, const real3& dn, uint32_t coefficients) {
  const double* g = p.data() + size_t(id) * kGaussFloats + kGaussSH;
  real3 c(0.5);
  for (uint32_t k = 0; k < coefficients; k++) c += shBasis(k, dn) * real3(g[3 * k], g[3 * k + 1], g[3 * k + 2]);
  return c;
}

}  // namespace

RayD toRayD(const GpuRay& r) {
  return {{r.origin[0], r.origin[1], r.origin[2]}, {r.dir[0], r.dir[1], r.dir[2]}, r.tmin, r.tmax};
}

std::vector<double> toDouble(const GaussianSet& set) { return std::vector<double>(set.params.begin(), set.params.end()); }

TraceResultD traceRayRef(const std::vector<double>& p, const RayD& ray, const TraceOptionsD& options) {
  TraceResultD res;
  real3 o(ray.origin[0], ray.origin[1], ray.origin[2]), d(ray.dir[0], ray.dir[1], ray.dir[2]);
  real3 dn = normalize(d);
  uint32_t coefficients = shCoefficientsFor(options.shDegree);
  std::vector<HitD> hits = collectHits(p, o, d, ray.tmin, ray.tmax, res.margin);
  real3 rgb(0);
  double T = 1;
  for (const HitD& h : hits) {
    double alpha = clampedAlpha(h.rawAlpha);
    real3 cRaw = shColorRaw(p, h.id, dn, coefficients);
    real3 c = max(cRaw, real3(0));
    res.margin = std::min({res.margin, std::fabs(cRaw.x), std::fabs(cRaw.y), std::fabs(cRaw.z)});  // the clamp's kink
    rgb += T * alpha * c;
    if (options.depthAtOpacity == 0) {
      res.depth += T * alpha * h.t;
    } else {
      if (1 - T < options.depthAtOpacity && 1 - T * (1 - alpha) >= options.depthAtOpacity) res.depth = h.t;
      res.margin = std::min(res.margin, relDist(1 - T * (1 - alpha), options.depthAtOpacity));  // the level's crossing
    }
    T *= 1 - alpha;
    res.hits++;
    res.margin = std::min(res.margin, relDist(T, options.minTransmittance));
    if (T < options.minTransmittance) break;
  }
  for (int c = 0; c < 3; c++) res.rgb[c] = rgb[c] + T * options.background[c];
  res.transmittance = T;
  res.opacity = 1 - T;
  return res;
}

RayGradD traceRayBackwardRef(const std::vector<double>& p, const RayD& ray, const double dLoss[4], std::vector<double>& dParams,
                             const TraceOptionsD& options, std::vector<double>* stats) {
  RayGradD out;
  // a ray without a loss gradient (a masked pixel) changes nothing and counts in no statistic
  if (dLoss[0] == 0 && dLoss[1] == 0 && dLoss[2] == 0 && dLoss[3] == 0) return out;
  TraceResultD fwd = traceRayRef(p, ray, options);
  real3 o(ray.origin[0], ray.origin[1], ray.origin[2]), d(ray.dir[0], ray.dir[1], ray.dir[2]);
  real3 dn = normalize(d);
  uint32_t coefficients = shCoefficientsFor(options.shDegree);
  double margin = 1e300;
  std::vector<HitD> hits = collectHits(p, o, d, ray.tmin, ray.tmax, margin);
  real3 C(fwd.rgb[0], fwd.rgb[1], fwd.rgb[2]), gC(dLoss[0], dLoss[1], dLoss[2]);
  double gA = dLoss[3], Tfinal = fwd.transmittance, T = 1;
  real3 Cprefix(0), dOrigin(0), dDir(0), dDirUnit(0);
  const double* vp = options.statisticsViewpoint;
  double distanceBefore = options.useStatisticsViewpoint ? length(o - real3(vp[0], vp[1], vp[2])) : 0.0;
  for (const HitD& h : hits) {
    double* g = dParams.data() + size_t(h.id) * kGaussFloats;
    const double* pg = p.data() + size_t(h.id) * kGaussFloats;
    double alpha = clampedAlpha(h.rawAlpha);
    real3 cRaw = shColorRaw(p, h.id, dn, coefficients);
    real3 c = max(cRaw, real3(0));
    double w = T * alpha;
    Cprefix += w * c;
    double oneMinus = 1 - alpha;
    double dAlpha = dot(gC, T * c - (C - Cprefix) / oneMinus) + gA * Tfinal / oneMinus;
    real3 dColor = w * gC * real3(cRaw.x > 0, cRaw.y > 0, cRaw.z > 0);
    for (uint32_t k = 0; k < coefficients; k++) {
      double Y = shBasis(k, dn);
      real3 coef(pg[kGaussSH + 3 * k], pg[kGaussSH + 3 * k + 1], pg[kGaussSH + 3 * k + 2]);
      for (int ch = 0; ch < 3; ch++) g[kGaussSH + 3 * k + ch] += dColor[ch] * Y;
      dDirUnit += dot(dColor, coef) * shBasisGradient(k, dn);
    }
    if (h.rawAlpha < kMaxAlpha) {
      GaussianD G = gaussianAt(p, h.id);
      real t;
      real3 r, x;
      real m = gaussianPeak(o, d, G.mu, G.M, t, r, x);
      double kernel = exp(-0.5 * m);
      double dm = dAlpha * (-0.5 * G.density * kernel);
      real3 dp, dw;
      real3x3 dM, dR;
      real3 dLogScale;
      peakBackward(dm, G.M, r, x, t, dp, dw, dM);
      localBackward(dM, G.M, G.invScale, dR, dLogScale);
      real4 dq = rotationBackward(G.q, dR);
      for (int a = 0; a < 3; a++) {
        g[kGaussMean + a] -= dp[a];
        g[kGaussLogScale + a] += dLogScale[a];
      }
      for (int a = 0; a < 4; a++) g[kGaussRotation + a] += dq[a];
      g[kGaussLogitDensity] += dAlpha * kernel * G.density * (1 - G.density);
      dOrigin += dp;
      dDir += dw;
      if (stats) (*stats)[2 * h.id] += length(dp) * (distanceBefore + t * length(d)) * 0.5;
    }
    if (stats) (*stats)[2 * h.id + 1] += 1;
    T *= oneMinus;
    if (T < options.minTransmittance) break;
  }
  dDir += normalizeBackward(d, dDirUnit);
  for (int a = 0; a < 3; a++) {
    out.dOrigin[a] = dOrigin[a];
    out.dDir[a] = dDir[a];
  }
  return out;
}

}  // namespace refrax::ref
