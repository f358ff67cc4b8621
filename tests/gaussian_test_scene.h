#pragma once
// Shared by the Gaussian tracer tests: random scenes and rays, and the comparison of GPU
// forward results with the double reference.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/gaussian/gaussian_trace.h"
#include "engine/reference/gaussian_trace_ref.h"
#include "engine/reference/random_rays.h"

namespace refrax::test {

// Gaussians in [-0.5,0.5]^2 x [-1,0] (sigma 0.02..0.06): about 60 candidates per ray.
inline RandomGaussianOptions testGaussianOptions() {
  RandomGaussianOptions o;
  o.sigmaMin = 0.02f;
  o.sigmaMax = 0.06f;
  return o;
}

// Rays from above the volume towards random points inside it.
inline std::vector<GpuRay> raysIntoVolume(std::mt19937& rng, size_t n) {
  return ref::randomRays(rng, n, {{-0.7f, -0.7f, 0.5f}, {0.7f, 0.7f, 1.5f}, {-0.5f, -0.5f, -1.0f}, {0.5f, 0.5f, 0.0f}}, 100.0f);
}

struct ForwardComparison {
  size_t rays = 0, compared = 0, skippedNearThreshold = 0, hitCountMismatch = 0;
  double worstColorRel = 0;  // max over rays and channels of |gpu - ref| / max(|ref|, 0.01)
  double worstOpacity = 0;   // max |gpu - ref|
  double worstDepthRel = 0;  // max |gpu - ref| / max(|ref|, 0.01)
  double meanHits = 0;
  size_t poisoned = 0;  // results with NaN
  std::string firstProblem;
};

// Rays whose reference result sits within `margin` of a discontinuity are skipped (a float
// tracer may legitimately decide differently there); they are counted.
inline ForwardComparison compareForward(const GaussianSet& set, const std::vector<GpuRay>& rays, const std::vector<GpuTraceResult>& gpu,
                                        const ref::TraceOptionsD& options, double margin = 1e-4) {
  ForwardComparison c;
  c.rays = rays.size();
  std::vector<double> params = ref::toDouble(set);
  double hitSum = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    const GpuTraceResult& g = gpu[i];
    if (std::isnan(g.rgb[0]) || std::isnan(g.rgb[1]) || std::isnan(g.rgb[2]) || std::isnan(g.opacity) || std::isnan(g.depth)) {
      c.poisoned++;
      continue;
    }
    ref::TraceResultD r = ref::traceRayRef(params, ref::toRayD(rays[i]), options);
    if (r.margin < margin) {
      c.skippedNearThreshold++;
      continue;
    }
    c.compared++;
    hitSum += r.hits;
    if (g.hits != r.hits) {
      c.hitCountMismatch++;
      if (c.firstProblem.empty())
        c.firstProblem = "ray " + std::to_string(i) + ": gpu " + std::to_string(g.hits) + " hits, reference " + std::to_string(r.hits);
    }
    for (int ch = 0; ch < 3; ch++) c.worstColorRel = std::max(c.worstColorRel, std::fabs(g.rgb[ch] - r.rgb[ch]) / std::max(std::fabs(r.rgb[ch]), 0.01));
    c.worstOpacity = std::max(c.worstOpacity, std::fabs(g.opacity - r.opacity));
    c.worstDepthRel = std::max(c.worstDepthRel, std::fabs(g.depth - r.depth) / std::max(std::fabs(r.depth), 0.01));
  }
  c.meanHits = c.compared ? hitSum / double(c.compared) : 0;
  return c;
}

inline ref::TraceOptionsD toOptionsD(const TraceOptions& o) {
  ref::TraceOptionsD d;
  for (int c = 0; c < 3; c++) d.background[c] = o.background[c];
  d.shDegree = o.shDegree;
  d.minTransmittance = o.minTransmittance;
  d.depthAtOpacity = o.depthAtOpacity;
  d.useStatisticsViewpoint = o.statisticsViewpoint.has_value();
  if (o.statisticsViewpoint)
    for (int a = 0; a < 3; a++) d.statisticsViewpoint[a] = (*o.statisticsViewpoint)[a];
  return d;
}

}  // namespace refrax::test
