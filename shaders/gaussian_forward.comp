#version 460
// Gaussian ray tracer, forward (3DGRT k-buffer, DESIGN 1.4): per ray, blend the accepted
// Gaussian hits front to back in (t, id) order, K at a time, until the transmittance drops
// below the minimum transmittance (push constant; kMinTransmittance by default) or nothing
// is left; colour from SH along the ray direction (+0.5, clamped at 0), then the background
// with the remaining transmittance. A training forward also records the blended hits for
// the backward (HitRecord).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "gaussian_trace_types.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int K = 16;
layout(constant_id = 1) const bool kInstanced = false;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) restrict readonly buffer Trace { TraceGaussian tg[]; };
layout(std430, set = 0, binding = 2) restrict readonly buffer ShPacked { vec4 shPacked[]; };
layout(std430, set = 0, binding = 3) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Results { TraceResult results[]; };
// written only for the first pc.recordsPerRay hits of each ray (see HitRecord)
layout(std430, set = 0, binding = 5) writeonly buffer HitRecords { HitRecord hitRecords[]; };
REFRAX_TRACE_PUSH
#include "gaussian_kbuffer.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray ray = rays[i];
  vec3 o = ray.originTmin.xyz, d = ray.dirTmax.xyz;
  vec3 dn = normalize(d);
  uint coefficients = shCoefficientsFor(pc.shDegree);
  float T = 1.0, depth = 0.0, tcur = ray.originTmin.w;
  uint idcur = 0xFFFFFFFFu;  // nothing at t == tmin counts
  vec3 rgb = vec3(0.0);
  uint hits = 0u, rounds = 0u;
  for (;;) {
    rounds++;
    int n = collectHits(o, d, tcur, idcur, ray.dirTmax.w);
    // the SH basis only for rays that hit something (many rays of a sparse scene do not)
    if (rounds == 1u && n > 0) evaluateShBasis(dn, coefficients);
    for (int k = 0; k < n; k++) {
      float alpha = clampedAlpha(ka[k]);
      loadShCoefficients(kid[k], coefficients);
      vec3 c = max(shColorRaw(), vec3(0.0));
      rgb += (T * alpha) * c;
      depth += T * alpha * kt[k];
      T *= 1.0 - alpha;
      if (hits < pc.recordsPerRay) hitRecords[i * pc.recordsPerRay + hits] = HitRecord(kid[k], floatBitsToUint(ka[k]));
      hits++;
      if (T < pc.minTransmittance) break;
    }
    if (T < pc.minTransmittance || n < K || rounds >= pc.maxRounds) break;
    tcur = kt[K - 1];
    idcur = kid[K - 1];
  }
  rgb += T * pc.background.rgb;
  results[i] = TraceResult(vec4(rgb, 1.0 - T), depth, T, hits, rounds);
}
