// The Gaussian tracer's per-ray forward output (std430, one source for the shaders and the
// host: layout_prelude.glsl; the host's GpuTraceResult in engine/gaussian/gaussian_trace.h).
#ifndef REFRAX_TRACE_RESULT_GLSL
#define REFRAX_TRACE_RESULT_GLSL
#include "layout_prelude.glsl"
LAYOUT_STRUCT(TraceResult, GpuTraceResult)
  LAYOUT_XYZ_W(rgb, opacity, rgbOpacity)  // opacity = 1 - transmittance
  LAYOUT_FLOAT(depth)          // sum of T_k alpha_k t_k (not normalised)
  LAYOUT_FLOAT(transmittance)  // T after the last blended hit (the background's weight)
  LAYOUT_UINT(hits)            // hits blended
  LAYOUT_UINT(rounds)          // k-buffer rounds traced
LAYOUT_END(GpuTraceResult, 32)
#endif
