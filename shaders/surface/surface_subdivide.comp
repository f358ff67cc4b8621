#version 460
// One level of recursive subdivision tracing: each ray is tested only against the 4
// children (at `level`) of its triangle (at `level` - 1), no BVH. The nearest child hit
// wins; a ray missing all 4 keeps the child whose plane point lies least outside it.
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 1) buffer Records { SurfaceRecord records[]; };
layout(std430, set = 0, binding = 2) readonly buffer GridHeights { float gridHeights[]; };
layout(std430, set = 0, binding = 3) readonly buffer LatticeIndex { uint latticeIndex[]; };
layout(std430, set = 0, binding = 4) readonly buffer PointHeights { float pointHeights[]; };
layout(std430, set = 0, binding = 5) buffer Counters { uint counters[]; };
#define SURFACE_LOOKUP
#include "surface_lattice.glsl"
void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  SurfaceRecord rec = records[r];
  uint flags = surfaceRecordFlags(rec);
  if ((flags & kSurfaceHit) == 0u) return;
  vec3 o, d;
  float tmin, tmax;
  loadRay(rays[r].originTmin, rays[r].dirTmax, o, d, tmin, tmax);
  int i, j;
  unpackCell(rec.cell, i, j);
  int side = int(surfaceRecordSide(rec));
  int bestInside = -1, bestOutside = -1;
  float bestT = 0.0, bestOut = 0.0;
  vec3 tuvs[4];
  bool ok = true;
  for (int c = 0; c < 4; c++) {
    int ci, cj, cs;
    childTriangle(i, j, side, c, ci, cj, cs);
    vec3 P[3];
    for (int k = 0; k < 3; k++) {
      int X, Y;
      finestCorner(ci, cj, cs, k, pc.level, X, Y);
      P[k] = latticeVertex(X, Y, ok);
    }
    bool planeOk = rayTrianglePlane(o, d, P[0], P[1], P[2], kPlaneEps, tuvs[c]);
    considerChild(c, planeOk, tuvs[c], tmin, tmax, bestInside, bestT, bestOutside, bestOut);
  }
  int best = bestInside >= 0 ? bestInside : bestOutside;
  if (!ok) {
    flags = (flags & ~kSurfaceHit) | kSurfaceLookupFailed;
    atomicAdd(counters[kCountLookupFailed], 1u);
  } else if (best < 0) {
    flags = (flags & ~kSurfaceHit) | kSurfaceDegenerate;
    atomicAdd(counters[kCountDegenerate], 1u);
  } else {
    if (bestInside < 0 && (flags & kSurfaceFallback) == 0u) {
      flags |= kSurfaceFallback;
      atomicAdd(counters[kCountFallback], 1u);
    }
    int ci, cj, cs;
    childTriangle(i, j, side, best, ci, cj, cs);
    rec.cell = packCell(ci, cj);
    rec.t = tuvs[best].x;
    rec.u = tuvs[best].y;
    rec.v = tuvs[best].z;
    side = cs;
  }
  rec.info = uint(side) | (uint(pc.level) << 1) | (flags << 8);
  records[r] = rec;
}
