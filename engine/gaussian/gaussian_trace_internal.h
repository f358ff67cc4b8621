#pragma once
// What the Gaussian tracer's host files share (gaussian_trace.cpp, tiled_trace.cpp); not an
// interface for other callers.
#include <cstdint>
#include <vector>

#include "engine/gaussian/gaussian_trace.h"

namespace refrax {

// Push constants of the forward and backward shaders (REFRAX_TRACE_PUSH, gaussian_trace_types.glsl).
struct TracePush {
  float background[4];
  uint32_t count, shDegree, maxRounds;
  float minTransmittance;  // forward only (the backward's slot is padding)
  float statViewpoint[4];  // backward only
  uint32_t recordsPerRay;
  uint32_t imageWidth, tileCapacity;  // tiled forward only
  float depthAtOpacity;  // forward only
};
static_assert(sizeof(TracePush) == 64, "TracePush must match REFRAX_TRACE_PUSH (gaussian_trace_types.glsl)");

// The options as push constants (checked: one clear error for a bad value).
TracePush tracePush(uint32_t count, const TraceOptions& options);
// Specialization constants of the tracer shaders: K and the proxy variant.
std::vector<SpecConstant> traceSpec(uint32_t K, ProxyKind kind);
// Rays from the host: a NaN or zero direction would turn into NaN colours and gradients.
void validateRays(const std::vector<GpuRay>& rays);

}  // namespace refrax
