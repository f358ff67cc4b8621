#version 460
// Global intersection: one ray query per camera ray against the coarse proxy mesh. Writes
// each ray's record: its coarse triangle (level 0), or a miss/invalid flag (counted).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_lattice.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
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
  records[r] = rec;
}
