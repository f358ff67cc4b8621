#pragma once
// CPU double-precision reference of the Gaussian ray tracer, forward and backward,
// independent of any BVH: every Gaussian is tested against every ray, all accepted hits
// are sorted by (t, id) and blended with the same rules as the shaders (the k-buffer must
// give the same result as this full sort). The math comes from the shared header
// (shaders/include/gaussian_math.glsl in refrax::f64).
#include <cstdint>
#include <vector>

#include "engine/gaussian/gaussians.h"
#include "engine/trace/rays.h"

namespace refrax::ref {

struct RayD {
  double origin[3];
  double dir[3];
  double tmin, tmax;
};
RayD toRayD(const GpuRay& r);

struct TraceOptionsD {
  double background[3] = {0, 0, 0};
  uint32_t shDegree = 3;
  double minTransmittance = 1e-3;  // the forward's early stop (TraceOptions::minTransmittance)
  double depthAtOpacity = 0;       // TraceOptions::depthAtOpacity
  bool useStatisticsViewpoint = false;  // TraceOptions::statisticsViewpoint
  double statisticsViewpoint[3] = {0, 0, 0};
};

struct TraceResultD {
  double rgb[3] = {0, 0, 0};
  double opacity = 0;
  double depth = 0;
  double transmittance = 1;
  uint32_t hits = 0;
  // Smallest relative distance of any quantity to a threshold that changes the result
  // discontinuously (hit acceptance, alpha clamp, early stop, t range, equal t of two
  // hits). A float tracer may decide differently where this is below ~1e-5.
  double margin = 1e300;
};

// params: kGaussianFloats doubles per Gaussian (raw, as in GaussianSet).
TraceResultD traceRayRef(const std::vector<double>& params, const RayD& ray, const TraceOptionsD& options = {});

struct RayGradD {
  double dOrigin[3] = {0, 0, 0};
  double dDir[3] = {0, 0, 0};
};
// Analytic gradient of L = dot(dLoss.rgb, rgb) + dLoss[3] * opacity for one ray; parameter
// gradients are added into `dParams` (kGaussianFloats per Gaussian), and, when given, the
// densification statistics into `stats` (2 per Gaussian: |dL/dmean| * distance / 2 summed
// over rays, and the number of rays that blended the Gaussian; a ray whose dLoss is all zero,
// a masked pixel, counts in neither).
RayGradD traceRayBackwardRef(const std::vector<double>& params, const RayD& ray, const double dLoss[4], std::vector<double>& dParams,
                             const TraceOptionsD& options = {}, std::vector<double>* stats = nullptr);

std::vector<double> toDouble(const GaussianSet& set);

}  // namespace refrax::ref
