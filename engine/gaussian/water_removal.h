#pragma once
// Water removal: the learned Gaussians seen from a camera with the water taken away, i.e.
// the Gaussian tracer's forward on straight camera rays (engine/camera/camera_rays.h), no surface
// and no refraction.
#include <vector>

#include "engine/camera/camera.h"
#include "engine/camera/camera_rays.h"
#include "engine/gaussian/gaussian_trace.h"

namespace refrax {

// Renders every pixel of `camera`; results row-major. `rays`, when given, receives the
// camera rays traced (for checks).
std::vector<GpuTraceResult> renderWithoutWater(Context& ctx, GaussianTracer& tracer, const CameraRayPipelines& cameraRays,
                                               const GaussianProxies& proxies, const DeviceGaussians& gaussians, const Camera& camera,
                                               const TraceOptions& options = {}, std::vector<GpuRay>* rays = nullptr);

}  // namespace refrax
