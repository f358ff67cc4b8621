#version 460
// A triangle mesh swapped in for the water (engine/mesh_surface.h): one ray query per ray,
// closest opaque hit; at the hit, the interpolated vertex normal and Snell's law give the
// refracted ray. A mesh that is a regular height grid (engine/grid_mesh.h: a baked learned
// surface, a built-in one; kGrid) is walked cell by cell along the ray instead (a 2D DDA
// over the cells the ray crosses inside the grid's height range, both triangles of each
// tested), the same triangles without a BVH walk, which is slow on CPU devices. Output conventions are those of surface_refract.comp, so the Gaussian tracer
// treats both alike: a hit gives (origin p, tmin 0, unit direction w, tmax = what was left of
// the ray's range); a miss continues unchanged; an invalid ray becomes an empty ray
// (origin 0, tmin = tmax = 0).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "mesh_refract.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const bool kGrid = false;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) readonly buffer Positions { float positions[]; };  // xyz per vertex (the BLAS input)
layout(std430, set = 0, binding = 3) readonly buffer Normals { float normals[]; };      // unit xyz per vertex
layout(std430, set = 0, binding = 4) readonly buffer Indices { uint indices[]; };       // 3 per triangle
layout(std430, set = 0, binding = 5) writeonly buffer Refracted { Ray refracted[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Flags { uint flags[]; };
layout(push_constant) uniform Push {
  uint count;
  float eta;
  uvec2 cells;   // kGrid: cells in x and y; vertex (i, j) is j * (cells.x + 1) + i
  vec4 domain;   // kGrid: x0 y0 x1 y1
  vec2 heights;  // kGrid: the lowest and highest vertex z
} pc;

vec3 positionAt(uint i) { return vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]); }
vec3 normalAt(uint i) { return vec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]); }

// Ray (unit d) against triangle (P0, P1, P2), Moeller-Trumbore: t in [tmin, tbest) and the
// barycentrics of P1 and P2; edges get a little slack so that a ray through a shared edge or
// a cell corner hits one of its triangles.
bool hitTriangle(vec3 o, vec3 d, vec3 P0, vec3 P1, vec3 P2, float tmin, float tbest, out float t, out vec2 bary) {
  vec3 e1 = P1 - P0, e2 = P2 - P0;
  vec3 q = cross(d, e2);
  float det = dot(e1, q);
  t = 0.0;
  bary = vec2(0.0);
  if (det == 0.0) return false;
  float inv = 1.0 / det;
  vec3 s = o - P0;
  float u = dot(s, q) * inv;
  vec3 r = cross(s, e1);
  float v = dot(d, r) * inv;
  const float kEdge = 1e-6;
  if (u < -kEdge || v < -kEdge || u + v > 1.0 + kEdge) return false;
  t = dot(e2, r) * inv;
  bary = vec2(u, v);
  return t >= tmin && t < tbest;
}

// The closest hit on the height grid in [tmin, tmax): triangle corners i0 i1 i2 and t, bary.
bool gridHit(vec3 o, vec3 d, float tmin, float tmax, out uvec3 corners, out float t, out vec2 bary) {
  corners = uvec3(0u);
  t = 0.0;
  bary = vec2(0.0);
  vec2 lo = pc.domain.xy, hi = pc.domain.zw;
  vec2 size = (hi - lo) / vec2(pc.cells);
  // the part of the ray inside the grid's box (z: the height range, padded for rounding)
  float pad = 1e-5 * (1.0 + max(abs(pc.heights.x), abs(pc.heights.y)));
  vec3 boxLo = vec3(lo, pc.heights.x - pad), boxHi = vec3(hi, pc.heights.y + pad);
  float t0 = tmin, t1 = tmax;
  for (int a = 0; a < 3; a++) {
    if (d[a] == 0.0) {
      if (o[a] < boxLo[a] || o[a] > boxHi[a]) return false;
      continue;
    }
    float ta = (boxLo[a] - o[a]) / d[a], tb = (boxHi[a] - o[a]) / d[a];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  if (t0 > t1) return false;
  vec2 p = (o.xy + t0 * d.xy - lo) / size;
  ivec2 cell = clamp(ivec2(floor(p)), ivec2(0), ivec2(pc.cells) - 1);
  ivec2 step = ivec2(d.x > 0.0 ? 1 : -1, d.y > 0.0 ? 1 : -1);
  // ray t at the next cell boundary in x and y, and between boundaries
  vec2 next, delta;
  for (int a = 0; a < 2; a++) {
    if (d[a] == 0.0) {
      next[a] = 3.4e38;
      delta[a] = 3.4e38;
    } else {
      float edge = lo[a] + float(cell[a] + (step[a] > 0 ? 1 : 0)) * size[a];
      next[a] = (edge - o[a]) / d[a];
      delta[a] = size[a] / abs(d[a]);
    }
  }
  float best = 3.4e38;
  uint stride = pc.cells.x + 1u;
  for (uint visits = 0u; visits < pc.cells.x + pc.cells.y + 1u; visits++) {
    uint a = uint(cell.y) * stride + uint(cell.x), b = a + 1u, c = a + stride, dd = c + 1u;
    vec3 A = positionAt(a), B = positionAt(b), C = positionAt(c), D = positionAt(dd);
    float th;
    vec2 bh;
    // the two triangles of grid_mesh.cpp: (a, b, d) and (a, d, c)
    if (hitTriangle(o, d, A, B, D, tmin, min(best, tmax), th, bh)) {
      best = th;
      corners = uvec3(a, b, dd);
      bary = bh;
    }
    if (hitTriangle(o, d, A, D, C, tmin, min(best, tmax), th, bh)) {
      best = th;
      corners = uvec3(a, dd, c);
      bary = bh;
    }
    // a hit in this cell comes before any in the cells further along the ray
    if (best < 3.4e38) break;
    float leave = min(next.x, next.y);
    if (leave > t1) break;
    if (next.x < next.y) {
      cell.x += step.x;
      next.x += delta.x;
    } else {
      cell.y += step.y;
      next.y += delta.y;
    }
    if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(pc.cells)))) break;
  }
  t = best;
  return best < 3.4e38;
}

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  Ray ray = rays[r];
  // As loadRay in surface_lattice.glsl: unit direction, tmin/tmax rescaled to it.
  float len = length(ray.dirTmax.xyz);
  vec3 o = ray.originTmin.xyz;
  vec3 d = ray.dirTmax.xyz / len;
  float tmin = ray.originTmin.w * len;
  float tmax = ray.dirTmax.w * len;
  bool finite = !any(isnan(ray.originTmin)) && !any(isinf(ray.originTmin)) && !any(isnan(ray.dirTmax)) && !any(isinf(ray.dirTmax));
  if (!(finite && len > 0.0 && !isinf(len) && tmin >= 0.0 && tmax >= tmin)) {
    refracted[r] = Ray(vec4(0.0), vec4(0.0, 0.0, -1.0, 0.0));
    flags[r] = kSurfaceInvalidRay;
    return;
  }
  uint i0, i1, i2;
  float t;
  vec2 bary;
  bool hit;
  if (kGrid) {
    uvec3 corners;
    hit = gridHit(o, d, tmin, tmax, corners, t, bary);
    i0 = corners.x;
    i1 = corners.y;
    i2 = corners.z;
  } else {
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, o, tmin, d, tmax);
    while (rayQueryProceedEXT(rq)) {}
    hit = rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
    uint tri = hit ? uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true)) : 0u;
    t = hit ? rayQueryGetIntersectionTEXT(rq, true) : 0.0;
    bary = hit ? rayQueryGetIntersectionBarycentricsEXT(rq, true) : vec2(0.0);
    i0 = indices[3 * tri];
    i1 = indices[3 * tri + 1];
    i2 = indices[3 * tri + 2];
  }
  if (!hit) {
    refracted[r] = ray;
    flags[r] = kSurfaceMissed;
    return;
  }
  vec3 P0 = positionAt(i0);
  vec3 face = cross(positionAt(i1) - P0, positionAt(i2) - P0);
  vec3 n, w;
  bool backFacing;
  meshHitRefract(d, bary.x, bary.y, normalAt(i0), normalAt(i1), normalAt(i2), face, pc.eta, n, w, backFacing);
  refracted[r] = Ray(vec4(o + t * d, 0.0), vec4(w, max(tmax - t, 0.0)));
  flags[r] = kSurfaceHit | (backFacing ? kSurfaceBackFacing : 0u);
}
