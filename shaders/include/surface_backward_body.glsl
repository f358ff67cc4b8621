// Body of the surface backward (surface_backward.comp with float atomics,
// surface_backward_cas.comp with a compare-and-swap loop): from dL/dp, dL/dw of each ray
// to dL/dz of every lattice point its finest triangle and vertex normals read.
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 1) readonly buffer Records { SurfaceRecord records[]; };
layout(std430, set = 0, binding = 2) readonly buffer RayGrads { RayGrad rayGrads[]; };
layout(std430, set = 0, binding = 3) readonly buffer GridHeights { float gridHeights[]; };
layout(std430, set = 0, binding = 4) readonly buffer LatticeIndex { uint latticeIndex[]; };
layout(std430, set = 0, binding = 5) readonly buffer PointHeights { float pointHeights[]; };
#ifdef REFRAX_FLOAT_ATOMICS
layout(std430, set = 0, binding = 6) buffer GridGrad { float gridGrad[]; };
layout(std430, set = 0, binding = 7) buffer PointGrad { float pointGrad[]; };
void atomicAddGrid(int k, float g) { atomicAdd(gridGrad[k], g); }
void atomicAddPoint(uint k, float g) { atomicAdd(pointGrad[k], g); }
#else
layout(std430, set = 0, binding = 6) buffer GridGrad { uint gridGrad[]; };
layout(std430, set = 0, binding = 7) buffer PointGrad { uint pointGrad[]; };
// float add as a compare-and-swap loop on the bits (devices without float atomics)
void atomicAddGrid(int k, float g) {
  uint old = gridGrad[k];
  for (;;) {
    uint prev = atomicCompSwap(gridGrad[k], old, floatBitsToUint(uintBitsToFloat(old) + g));
    if (prev == old) break;
    old = prev;
  }
}
void atomicAddPoint(uint k, float g) {
  uint old = pointGrad[k];
  for (;;) {
    uint prev = atomicCompSwap(pointGrad[k], old, floatBitsToUint(uintBitsToFloat(old) + g));
    if (prev == old) break;
    old = prev;
  }
}
#endif
layout(std430, set = 0, binding = 8) buffer Counters { uint counters[]; };
#define SURFACE_LOOKUP
#include "surface_lattice.glsl"

void addHeightGradient(int X, int Y, float g) {
  if (g == 0.0) return;
  if (isCoarsePoint(X, Y)) {
    atomicAddGrid(coarseIndex(X, Y), g);
    return;
  }
  int slot = latticeSlot(X, Y);
  if (slot >= 0 && latticeIndex[slot] < kClaimed) atomicAddPoint(latticeIndex[slot], g);
}

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  SurfaceRecord rec = records[r];
  if (((rec.info >> 8) & kSurfaceHit) == 0u) return;
  vec3 gp = rayGrads[r].dOrigin.xyz, gw = rayGrads[r].dDir.xyz;
  if (any(isnan(gp)) || any(isinf(gp)) || any(isnan(gw)) || any(isinf(gw))) {
    atomicAdd(counters[kCountNonFiniteGrad], 1u);
    return;
  }
  vec3 o, d;
  float tmin, tmax;
  loadRay(rays[r].originTmin, rays[r].dirTmax, o, d, tmin, tmax);
  int i, j;
  unpackCell(rec.cell, i, j);
  int side = int(rec.info & 1u);
  bool ok = true;
  vec3 P[3], N[3];
  int X[3], Y[3];
  for (int k = 0; k < 3; k++) {
    finestCorner(i, j, side, k, pc.levels, X[k], Y[k]);
    P[k] = latticeVertex(X[k], Y[k], ok);
    N[k] = vertexNormalAt(X[k], Y[k], ok);
  }
  if (!ok) return;  // the forward flagged it already
  vec3 gP[3], gN[3];
  surfaceHitBackward(o, d, P[0], P[1], P[2], N[0], N[1], N[2], (pc.options & kOptionFaceNormals) != 0u, pc.eta, gp, gw, gP[0], gP[1],
                     gP[2], gN[0], gN[1], gN[2]);
  for (int k = 0; k < 3; k++) {
    addHeightGradient(X[k], Y[k], gP[k].z);
    // N = (sum_m a_m z_m / hx, sum_m b_m z_m / hy, 6) over the ring
    for (int m = 0; m < 6; m++) {
      int di, dj;
      ringOffset(m, di, dj);
      addHeightGradient(X[k] + di, Y[k] + dj, ringWeightX(m) * gN[k].x / pc.spacing.x + ringWeightY(m) * gN[k].y / pc.spacing.y);
    }
  }
}
