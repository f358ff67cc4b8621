#version 460
// The refracting hit: on each ray's finest triangle, the intersection p, the Phong-style
// interpolated vertex normal (or the face normal) and Snell's law give the refracted ray
// (origin p, direction w) for the Gaussian tracer. Missed rays continue unrefracted;
// invalid rays become empty rays (tmin = tmax = 0).
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
layout(std430, set = 0, binding = 5) writeonly buffer Refracted { Ray refracted[]; };
// With kOptionHitNormals: per ray the hit normal and the 3 raw vertex normals (vec4 each).
layout(std430, set = 0, binding = 6) writeonly buffer HitNormals { vec4 hitNormals[]; };
layout(std430, set = 0, binding = 7) buffer Counters { uint counters[]; };
#define SURFACE_LOOKUP
#include "surface_lattice.glsl"
void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  SurfaceRecord rec = records[r];
  uint flags = surfaceRecordFlags(rec);
  Ray ray = rays[r];
  if ((flags & kSurfaceInvalidRay) != 0u) {
    refracted[r] = Ray(vec4(0.0), vec4(0.0, 0.0, -1.0, 0.0));
    return;
  }
  vec3 o, d;
  float tmin, tmax;
  loadRay(ray.originTmin, ray.dirTmax, o, d, tmin, tmax);
  if ((flags & kSurfaceHit) != 0u) {
    int i, j;
    unpackCell(rec.cell, i, j);
    int side = int(surfaceRecordSide(rec));
    bool ok = true;
    vec3 P[3], N[3];
    for (int k = 0; k < 3; k++) {
      int X, Y;
      finestCorner(i, j, side, k, pc.levels, X, Y);
      P[k] = latticeVertex(X, Y, ok);
      N[k] = vertexNormalAt(X, Y, ok);
    }
    vec3 tuv, p, n, w;
    bool backFacing;
    bool planeOk = surfaceHitForward(o, d, P[0], P[1], P[2], N[0], N[1], N[2], (pc.options & kOptionFaceNormals) != 0u, pc.eta, tuv,
                                     p, n, w, backFacing);
    if (!ok) {
      flags = (flags & ~kSurfaceHit) | kSurfaceLookupFailed;
      atomicAdd(counters[kCountLookupFailed], 1u);
    } else if (!planeOk) {
      flags = (flags & ~kSurfaceHit) | kSurfaceDegenerate;
      atomicAdd(counters[kCountDegenerate], 1u);
    } else {
      if (backFacing) {
        flags |= kSurfaceBackFacing;
        atomicAdd(counters[kCountBackFacing], 1u);
      }
      rec.t = tuv.x;
      rec.u = tuv.y;
      rec.v = tuv.z;
      refracted[r] = Ray(vec4(p, 0.0), vec4(w, max(tmax - tuv.x, 0.0)));
      if ((pc.options & kOptionHitNormals) != 0u) {
        hitNormals[4 * r] = vec4(n, 0.0);
        for (int k = 0; k < 3; k++) hitNormals[4 * r + 1 + k] = vec4(N[k], 0.0);
      }
    }
    rec.info = (rec.info & 0xFFu) | (flags << 8);
    records[r] = rec;
    if ((flags & kSurfaceHit) != 0u) return;
  }
  refracted[r] = ray;  // missed the domain (or degenerate): continues unrefracted
}
