// The Gaussian ray tracer's forward blend (3DGRT k-buffer, docs/method.md §1.4), shared by
// gaussian_forward.comp (any list of rays, hits from the BVH) and gaussian_forward_tiled.comp
// (an image's rays in tiles, hits from the tile's candidate list). Per ray: blend the accepted
// Gaussian hits front to back in (t, id) order, K at a time, until the transmittance drops
// below the minimum transmittance (push constant; kMinTransmittance by default) or nothing is
// left; colour from SH along the ray direction (+0.5, clamped at 0), then the background with
// the remaining transmittance. A training forward also records the blended hits for the
// backward (HitRecord).
//
// Before including: the bindings of gaussian_forward.comp, REFRAX_TRACE_PUSH,
// gaussian_kbuffer.glsl, and
//   uint forwardRayIndex()  // this invocation's ray, or kNoRay
//   int collectForward(vec3 o, vec3 d, float tcur, uint idcur, float tmax)  // as collectHits
#ifndef REFRAX_GAUSSIAN_FORWARD_BODY_GLSL
#define REFRAX_GAUSSIAN_FORWARD_BODY_GLSL
const uint kNoRay = 0xFFFFFFFFu;

void main() {
  uint i = forwardRayIndex();
  if (i == kNoRay) return;
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
    int n = collectForward(o, d, tcur, idcur, ray.dirTmax.w);
    // the SH basis only for rays that hit something (many rays of a sparse scene do not)
    if (rounds == 1u && n > 0) evaluateShBasis(dn, coefficients);
    for (int k = 0; k < n; k++) {
      float alpha = clampedAlpha(ka[k]);
      loadShCoefficients(kid[k], coefficients);
      vec3 c = max(shColorRaw(), vec3(0.0));
      rgb += (T * alpha) * c;
      // the expected depth, or the t where the opacity first reaches the level (depthAtOpacity)
      if (pc.depthAtOpacity == 0.0) depth += T * alpha * kt[k];
      else if (1.0 - T < pc.depthAtOpacity && 1.0 - T * (1.0 - alpha) >= pc.depthAtOpacity) depth = kt[k];
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
#endif
