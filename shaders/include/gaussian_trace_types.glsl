// Records of the Gaussian tracer shaders (GLSL only; host mirrors in engine/gaussian_trace.h).
#ifndef REFRAX_GAUSSIAN_TRACE_TYPES_GLSL
#define REFRAX_GAUSSIAN_TRACE_TYPES_GLSL
#include "gaussian_math.glsl"

// What the tracer reads per candidate: mean and density, and M = S^-1 R^T by columns; the
// Gaussian's id in m0.w (bits), the squared cut-off radius (slightly padded) in m1.w.
// Written by gaussian_prepare.comp in proxy order.
struct TraceGaussian {
  vec4 meanDensity;
  vec4 m0;
  vec4 m1;
  vec4 m2;
};

// Per-ray forward output (engine/gaussian_trace.h GpuTraceResult).
struct TraceResult {
  vec4 rgbOpacity;
  float depth;          // sum of T_k alpha_k t_k (not normalised)
  float transmittance;  // T after the last blended hit (the background's weight)
  uint hits;            // hits blended
  uint rounds;          // k-buffer rounds traced
};

#endif
