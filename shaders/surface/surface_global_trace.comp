#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Global intersection: one ray query per camera ray against the coarse proxy mesh (compute
// trace backend: a walk over the proxy grid's cells, include/grid_walk.glsl, the same
// triangles). Writes each ray's record: its coarse triangle (level 0), or a miss/invalid flag
// (counted).
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_lattice.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
#ifdef REFRAX_COMPUTE_TRACE
// the proxy mesh's vertices (surface_grid_vertices.comp) and their height range (surface_height_range.comp)
layout(std430, set = 0, binding = 0) readonly buffer Vertices { float vertices[]; };
layout(std430, set = 0, binding = 5) readonly buffer HeightRange { uint heightRange[2]; };
#include "ordered_float.glsl"
vec3 positionAt(uint i) { return vec3(vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]); }
#include "grid_walk.glsl"
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
#endif
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) readonly buffer CellOrder { uint cellOrder[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Records { SurfaceRecord records[]; };
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };
void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  vec3 o, d;
  float tmin, tmax;
  SurfaceRecord rec = SurfaceRecord(0u, 0u, -1.0, 0.0, 0.0, 0u, 0u, 0u);
  if (!loadRay(rays[r].originTmin, rays[r].dirTmax, o, d, tmin, tmax)) {
    rec.info = kSurfaceInvalidRay << 8;
    atomicAdd(counters[kCountInvalid], 1u);
    records[r] = rec;
    return;
  }
#ifdef REFRAX_COMPUTE_TRACE
  uvec3 corners;
  uvec2 cell;
  uint side;
  float t;
  vec2 bary;
  vec2 cellSize = pc.spacing * float(1 << pc.levels);
  vec4 domain = vec4(pc.origin, pc.origin + cellSize * vec2(pc.cellsX, pc.cellsY));
  vec2 heights = vec2(orderedToFloat(heightRange[0]), orderedToFloat(heightRange[1]));
  if (gridHit(o, d, tmin, tmax, uvec2(pc.cellsX, pc.cellsY), domain, heights, corners, cell, side, t, bary)) {
    rec.cell = packCell(int(cell.x), int(cell.y));
    rec.info = side | (kSurfaceHit << 8);
    rec.t = t;
    rec.u = bary.x;
    rec.v = bary.y;
  } else {
    rec.info = kSurfaceMissed << 8;
    atomicAdd(counters[kCountMissed], 1u);
  }
#else
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, o, tmin, d, tmax);
  while (rayQueryProceedEXT(rq)) {}
  if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    uint prim = uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
    uint cell = cellOrder[prim >> 1];
    rec.cell = packCell(int(cell % uint(pc.cellsX)), int(cell / uint(pc.cellsX)));
    rec.info = (prim & 1u) | (kSurfaceHit << 8);
    rec.t = rayQueryGetIntersectionTEXT(rq, true);
    vec2 bary = rayQueryGetIntersectionBarycentricsEXT(rq, true);
    rec.u = bary.x;
    rec.v = bary.y;
  } else {
    rec.info = kSurfaceMissed << 8;
    atomicAdd(counters[kCountMissed], 1u);
  }
#endif
  records[r] = rec;
}
