// Records of the Gaussian tracer shaders (GLSL only, but for TraceResult: trace_result.glsl).
#ifndef REFRAX_GAUSSIAN_TRACE_TYPES_GLSL
#define REFRAX_GAUSSIAN_TRACE_TYPES_GLSL
#include "gaussian_math.glsl"

// What the tracer reads per candidate (48 bytes): mean and density; the precision matrix
// A = M^T M as a00 a01 a02 a11 | a12 a22; the Gaussian's id (bits) and the squared cut-off
// radius (slightly padded). Written by gaussian_prepare.comp in proxy order.
struct TraceGaussian {
  vec4 meanDensity;
  vec4 a0;  // a00 a01 a02 a11
  vec4 a1;  // a12 a22 id radius^2
};

// SH coefficients packed per Gaussian id by gaussian_prepare.comp: the 48 floats of
// kGaussSH.. (coefficient k, channel c at 3k + c) as 12 vec4s.
const uint kShVec4s = 12u;

#include "trace_result.glsl"

// The hits a recording forward blended, in order, per ray (engine/gaussian/gaussian_trace.h
// HitRecords): x = Gaussian id, y = unclamped alpha (float bits). The backward reads them
// instead of traversing the BVH again.
#define HitRecord uvec2

// Push constants of the forward and the backward (engine/gaussian/gaussian_trace.cpp TracePush).
#define REFRAX_TRACE_PUSH                                                                            \
  layout(push_constant) uniform Push {                                                               \
    vec4 background;                                                                                 \
    uint count;                                                                                      \
    uint shDegree;                                                                                   \
    uint maxRounds;                                                                                  \
    float minTransmittance; /* forward: TraceOptions::minTransmittance (backward: the default) */    \
    vec4 statViewpoint;     /* backward, w = 1: statistics distances start here */                   \
    uint recordsPerRay;     /* hit records per ray (0: none are written or read) */                  \
    uint imageWidth;        /* tiled forward: the rays are an image this wide, row by row */         \
    uint tileCapacity;      /* tiled forward: candidates each tile's list holds */                   \
    float depthAtOpacity;   /* forward: TraceOptions::depthAtOpacity (0: the expected depth) */      \
  } pc;

#endif
