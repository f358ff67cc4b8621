#version 460
// Tiled Gaussian forward, stage 1 (engine/tiled_trace.h): one workgroup per 8x8 tile of an
// image's rays (row-major, width x height). The tile's rays are summed up as a cone
// (include/ray_bundle.glsl) and every Gaussian whose bounding sphere the cone may reach goes
// on the tile's candidate list. A list of up to kSortedMax is sorted by the depth of the
// sphere's centre along the cone's axis: the forward sorts each ray's hits by (t, id)
// whatever the list's order, but a ray then meets its hits nearly in order and the k-buffer's
// insertion rarely moves anything. counts[tile] is the true number, which may exceed the
// list's capacity: the forward then traverses the BVH for that tile instead.
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "ray_bundle.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, set = 0, binding = 0) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 1) readonly buffer Spheres { vec4 spheres[]; };  // centre, radius per trace record
layout(std430, set = 0, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Candidates { uint candidates[]; };  // capacity per tile
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint records;   // trace records (Gaussians)
  uint capacity;  // candidates per tile
} pc;

const uint kTileRays = 64u;
shared vec4 rayOrigin[kTileRays];  // w: 1 for a ray that can hit something
shared vec4 rayDir[kTileRays];     // unit direction
shared vec2 rayRange[kTileRays];   // [tmin, tmax] in units of the unit direction
shared vec4 coneOrigin;            // xyz, w = originRadius
shared vec4 coneDir;               // xyz, w = dirRadius
shared vec2 coneRange;             // sMin, sMax
shared bool coneEmpty;
shared uint listed;
const uint kSortedMax = 1024u;  // 8 KiB of shared memory for the keys and ids
shared float sortKey[kSortedMax];
shared uint sortId[kSortedMax];

void main() {
  uint lane = gl_LocalInvocationIndex;
  uvec2 px = gl_GlobalInvocationID.xy;
  uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  rayOrigin[lane] = vec4(0.0);
  if (px.x < pc.width && px.y < pc.height) {
    Ray r = rays[px.y * pc.width + px.x];
    float len = length(r.dirTmax.xyz);
    // an empty range (or a degenerate direction) reaches nothing
    if (r.dirTmax.w > r.originTmin.w && len > 0.0 && !isinf(len)) {
      rayOrigin[lane] = vec4(r.originTmin.xyz, 1.0);
      rayDir[lane] = vec4(r.dirTmax.xyz / len, 0.0);
      rayRange[lane] = vec2(r.originTmin.w, r.dirTmax.w) * len;
    }
  }
  barrier();
  if (lane == 0u) {
    // the axis: the mean origin and the normalised mean direction of the live rays
    vec3 o = vec3(0.0), d = vec3(0.0);
    float live = 0.0;
    for (uint k = 0u; k < kTileRays; k++) {
      if (rayOrigin[k].w == 0.0) continue;
      o += rayOrigin[k].xyz;
      d += rayDir[k].xyz;
      live += 1.0;
    }
    coneEmpty = live == 0.0;
    float originRadius = 0.0, dirRadius = 0.0, sMin = 3.4e38, sMax = 0.0;
    if (!coneEmpty) {
      o /= live;
      // directions that cancel leave no axis: a cone that culls nothing (dirRadius 2)
      bool axis = length(d) > 1e-6 * live;
      d = axis ? normalize(d) : vec3(0.0, 0.0, 1.0);
      for (uint k = 0u; k < kTileRays; k++) {
        if (rayOrigin[k].w == 0.0) continue;
        originRadius = max(originRadius, length(rayOrigin[k].xyz - o));
        dirRadius = max(dirRadius, length(rayDir[k].xyz - d));
        sMin = min(sMin, rayRange[k].x);
        sMax = max(sMax, rayRange[k].y);
      }
      if (!axis) dirRadius = 2.0;
    }
    coneOrigin = vec4(o, originRadius);
    coneDir = vec4(d, dirRadius);
    coneRange = vec2(sMin, sMax);
    listed = 0u;
  }
  barrier();
  if (!coneEmpty) {
    vec4 co = coneOrigin, cd = coneDir;
    vec2 cr = coneRange;
    for (uint g = lane; g < pc.records; g += kTileRays) {
      vec4 sphere = spheres[g];
      if (!bundleMayReachSphere(co.xyz, cd.xyz, co.w, cd.w, cr.x, cr.y, sphere.xyz, sphere.w)) continue;
      uint slot = atomicAdd(listed, 1u);
      if (slot < kSortedMax) {
        sortKey[slot] = dot(sphere.xyz - co.xyz, cd.xyz);
        sortId[slot] = g;
      } else if (slot < pc.capacity) {
        candidates[tile * pc.capacity + slot] = g;
      }
    }
  }
  barrier();
  uint n = listed;
  uint base = tile * pc.capacity;
  if (n <= kSortedMax && n <= pc.capacity) {
    // rank sort: each entry's place is the number of entries before it in (key, id) order
    // (n^2 / 64 comparisons per invocation and no further barriers, which cost more here
    // than the comparisons for the lists of a few hundred that tiles hold)
    for (uint i = lane; i < n; i += kTileRays) {
      float key = sortKey[i];
      uint rank = 0u;
      // equal keys in list order, so the ranks are a permutation
      for (uint j = 0u; j < n; j++) rank += uint(sortKey[j] < key) + uint(sortKey[j] == key && j < i);
      candidates[base + rank] = sortId[i];
    }
  } else {
    // too long to sort: the first kSortedMax as listed (the rest went straight to the list)
    for (uint i = lane; i < min(n, min(kSortedMax, pc.capacity)); i += kTileRays) candidates[base + i] = sortId[i];
  }
  if (lane == 0u) counts[tile] = n;
}
