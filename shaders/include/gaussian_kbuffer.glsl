// The k-buffer traversal shared by the Gaussian forward and backward shaders (GLSL only).
// Before including: the spec constants K (k-buffer size) and kInstanced (proxy variant),
// the acceleration structure `scene` (with REFRAX_COMPUTE_TRACE: the proxies' box BVH
// `bvhNodes`, shaders/include/box_bvh.glsl), the buffer `tg` of TraceGaussian and `shPacked`
// (SH coefficients, kShVec4s vec4s per Gaussian id).
//
// Each round collects the K closest accepted hits beyond the previous round's last hit,
// ordered by (t, Gaussian id) so that equal t values cannot be skipped or repeated; the
// caller blends them and starts the next round from the last one. Mathematically this
// visits the accepted hits in the same order as a full sort.
#ifndef REFRAX_GAUSSIAN_KBUFFER_GLSL
#define REFRAX_GAUSSIAN_KBUFFER_GLSL
float kt[K];
float ka[K];  // unclamped alpha (density * kernel)
uint kid[K];

bool keyBefore(float t0, uint id0, float t1, uint id1) { return t0 < t1 || (t0 == t1 && id0 < id1); }

// Tests the Gaussian of trace record `slot` against the ray and, when it is an accepted hit
// after (tcur, idcur) and before tmax that belongs among the K closest, inserts it in order.
// Returns whether it was inserted; n counts the buffer's hits.
bool insertCandidate(uint slot, vec3 o, vec3 d, float invLen2, float tcur, uint idcur, float tmax, inout int n) {
  // only what the test needs is loaded (each load is per lane on a CPU device)
  vec4 md = tg[slot].meanDensity;
  vec4 a0 = tg[slot].a0;
  vec2 a1 = tg[slot].a1.xy;
  mat3 A = mat3(a0.x, a0.y, a0.z, a0.y, a0.w, a1.x, a0.z, a1.x, a1.y);
  float t;
  float m = gaussianPeakPrecision(o, d, invLen2, md.xyz, A, t);
  // cheap pre-test before the exp: outside the (padded) cut-off ellipsoid acceptedAlpha
  // would reject the hit anyway
  if (m >= tg[slot].a1.w) return false;
  float a = acceptedAlpha(m, md.w);
  if (a == 0.0 || t >= tmax) return false;
  uint id = floatBitsToUint(tg[slot].a1.z);
  if (!keyBefore(tcur, idcur, t, id)) return false;
  if (n == K && !keyBefore(t, id, kt[K - 1], kid[K - 1])) return false;
  int j = min(n, K - 1);
  while (j > 0 && keyBefore(t, id, kt[j - 1], kid[j - 1])) {
    kt[j] = kt[j - 1];
    ka[j] = ka[j - 1];
    kid[j] = kid[j - 1];
    j--;
  }
  kt[j] = t;
  ka[j] = a;
  kid[j] = id;
  if (n < K) n++;
  return true;
}

// Fills kt/ka/kid with up to K accepted hits after (tcur, idcur) and before tmax, sorted;
// returns how many. The candidates are the proxies the ray query reports, or with the compute
// trace backend (REFRAX_COMPUTE_TRACE) the leaves of the proxies' box BVH the ray meets: the
// same candidates in another order, so the same hits.
#ifdef REFRAX_COMPUTE_TRACE
int collectHits(vec3 o, vec3 d, float tcur, uint idcur, float tmax) {
  int n = 0;
  float invLen2 = 1.0 / dot(d, d);
  float tq = max(0.0, tcur - 1e-5 * (1.0 + abs(tcur)));
  float t1 = tmax;  // shrinks to the K-th hit once the buffer is full, as the ray query's
  vec3 invD = vec3(1.0) / d;
  uint stack[kBvhStack];
  int sp = 0;
  stack[sp++] = 0u;
  while (sp > 0) {
    BvhNode node = bvhNodes[stack[--sp]];
    if (!bvhBoxHit(node.lo, node.hi, o, invD, tq, t1)) continue;
    if (node.left != kBvhLeaf) {
      stack[sp++] = node.right;  // the depth is at most 24 (16M proxies), the stack 64
      stack[sp++] = node.left;
      continue;
    }
    if (insertCandidate(node.right, o, d, invLen2, tcur, idcur, tmax, n) && n == K) t1 = kt[K - 1];
  }
  return n;
}
#else
int collectHits(vec3 o, vec3 d, float tcur, uint idcur, float tmax) {
  int n = 0;
  float invLen2 = 1.0 / dot(d, d);
  rayQueryEXT rq;
  // a little before tcur, so a Gaussian peaking right at tcur still overlaps the interval
  float tq = max(0.0, tcur - 1e-5 * (1.0 + abs(tcur)));
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsNoOpaqueEXT, 0xFF, o, tq, d, tmax);
  while (rayQueryProceedEXT(rq)) {
    if (rayQueryGetIntersectionTypeEXT(rq, false) != gl_RayQueryCandidateIntersectionAABBEXT) continue;
    uint slot = kInstanced ? rayQueryGetIntersectionInstanceCustomIndexEXT(rq, false)
                           : rayQueryGetIntersectionPrimitiveIndexEXT(rq, false);
    // buffer full: shrink the ray to the K-th hit so traversal culls everything beyond
    if (insertCandidate(slot, o, d, invLen2, tcur, idcur, tmax, n) && n == K) rayQueryGenerateIntersectionEXT(rq, kt[K - 1]);
  }
  return n;
}
#endif

// SH basis along the ray, evaluated once per ray (it depends only on the direction).
float shY[16];
void evaluateShBasis(vec3 dn, uint coefficients) {
  for (uint k = 0u; k < kShCoefficients; k++) shY[k] = k < coefficients ? shBasis(k, dn) : 0.0;  // unrolls, each folds
}

// SH coefficients of one Gaussian, loaded once per hit (the backward reuses them).
vec3 shC[16];
void loadShCoefficients(uint id, uint coefficients) {
  uint base = id * kShVec4s;
  // 3 vec4s hold 4 coefficients: (c0 c1.r) (c1.gb c2.rg) (c2.b c3)
  for (uint j = 0u; j < kShVec4s / 3u; j++) {  // constant bound: unrolls
    vec4 a = vec4(0.0), b = vec4(0.0), c = vec4(0.0);
    if (4u * j < coefficients) {
      a = shPacked[base + 3u * j];
      b = shPacked[base + 3u * j + 1u];
      c = shPacked[base + 3u * j + 2u];
    }
    // coefficients beyond the degree read as 0, as their basis values are
    shC[4u * j] = a.xyz;
    shC[4u * j + 1u] = 4u * j + 1u < coefficients ? vec3(a.w, b.xy) : vec3(0.0);
    shC[4u * j + 2u] = 4u * j + 2u < coefficients ? vec3(b.zw, c.x) : vec3(0.0);
    shC[4u * j + 3u] = 4u * j + 3u < coefficients ? c.yzw : vec3(0.0);
  }
}

// SH colour of the loaded Gaussian with the ray's basis shY (+0.5, before the clamp at 0).
vec3 shColorRaw() {
  vec3 c = vec3(0.5);
  for (uint k = 0u; k < kShCoefficients; k++) c += shY[k] * shC[k];
  return c;
}
#endif
