#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// A triangle mesh swapped in for the water (engine/surface/mesh_surface.h): one ray query per ray,
// closest opaque hit; at the hit, the interpolated vertex normal and Snell's law give the
// refracted ray. A mesh that is a regular height grid (engine/surface/grid_mesh.h: a baked learned
// surface, a built-in one; kGrid) is walked cell by cell along the ray instead (a 2D DDA
// over the cells the ray crosses inside the grid's height range, both triangles of each
// tested), the same triangles without a BVH walk, which is slow on CPU devices. Output conventions are those of surface_refract.comp, so the Gaussian tracer
// treats both alike: a hit gives (origin p, tmin 0, unit direction w, tmax = what was left of
// the ray's range); a miss continues unchanged; an invalid ray becomes an empty ray
// (origin 0, tmin = tmax = 0).
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "mesh_refract.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const bool kGrid = false;
#ifdef REFRAX_COMPUTE_TRACE
// compute trace backend: a BVH over the triangles' boxes (engine/trace/box_bvh.h), leaf k = triangle k
#include "box_bvh.glsl"
layout(std430, set = 0, binding = 0) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
#endif
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

#include "grid_walk.glsl"

#ifdef REFRAX_COMPUTE_TRACE
#include "triangle_bvh.glsl"
#endif

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
    uvec2 cell;
    uint side;
    hit = gridHit(o, d, tmin, tmax, pc.cells, pc.domain, pc.heights, corners, cell, side, t, bary);
    i0 = corners.x;
    i1 = corners.y;
    i2 = corners.z;
  } else {
#ifdef REFRAX_COMPUTE_TRACE
    uint tri;
    hit = bvhClosestTriangle(o, d, tmin, tmax, tri, t, bary);
#else
    rayQueryEXT rq;
    rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, o, tmin, d, tmax);
    while (rayQueryProceedEXT(rq)) {}
    hit = rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
    uint tri = hit ? uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true)) : 0u;
    t = hit ? rayQueryGetIntersectionTEXT(rq, true) : 0.0;
    bary = hit ? rayQueryGetIntersectionBarycentricsEXT(rq, true) : vec2(0.0);
#endif
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
