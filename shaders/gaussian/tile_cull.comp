#version 460
// Tiled Gaussian forward, culling (engine/gaussian/tiled_trace.h). One workgroup per square block of
// an image's rays (row-major, width x height): the block's rays are summed up as a cone
// (include/ray_bundle.glsl) and every Gaussian whose bounding sphere the cone may reach goes
// on the block's list. Two levels (push constant `level`):
//   0: blocks of kBlockSide^2 rays test every Gaussian; their lists are unsorted;
//   1: the 8x8 tiles the forward reads test only their block's list (every Gaussian when
//      that list overflowed), and a list of up to kSortedMax is ordered by the depth of the
//      sphere's centre along the cone's axis, in kBuckets buckets over the list's depth range
//      (a counting sort: order within a bucket is arbitrary). The forward sorts each ray's
//      hits by (t, id) whatever the list's order, but a ray then meets its hits nearly in
//      order and the k-buffer's insertion rarely moves anything.
// counts[list] is the true number, which may exceed the list's capacity: a tile's forward
// then traverses the BVH instead.
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "ray_bundle.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 1) readonly buffer Spheres { vec4 spheres[]; };  // centre, radius per trace record
layout(std430, set = 0, binding = 2) readonly buffer ParentCounts { uint parentCounts[]; };          // level 1: the blocks'
layout(std430, set = 0, binding = 3) readonly buffer ParentLists { uint parentLists[]; };            // level 1: the blocks'
layout(std430, set = 0, binding = 4) writeonly buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Candidates { uint candidates[]; };  // capacity per list
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint records;         // trace records (Gaussians)
  uint capacity;        // entries per list written
  uint side;            // rays per side of this level's blocks
  uint level;           // 0: blocks from every record; 1: tiles from their block's list, sorted
  uint parentCapacity;  // level 1: entries per block list
  uint parentSide;      // level 1: rays per side of a block
} pc;

const uint kLanes = 64u;
shared vec4 partOrigin[kLanes];  // per lane: sum of origins, w = live rays
shared vec3 partDir[kLanes];     // per lane: sum of unit directions
shared vec4 partSpread[kLanes];  // per lane: max origin and direction deviations, min s, max s
shared vec4 coneOrigin;          // xyz, w = originRadius
shared vec4 coneDir;             // xyz, w = dirRadius
shared vec2 coneRange;           // sMin, sMax
shared bool coneEmpty;
shared uint listed;
const uint kSortedMax = 2048u;  // 16 KiB of shared memory for the keys and ids (32 KiB on lavapipe in all)
shared float sortKey[kSortedMax];
shared uint sortId[kSortedMax];
const uint kBuckets = 64u;
shared uint bucketStart[kBuckets];
shared uint bucketFill[kBuckets];
shared uint keyLow, keyHigh;  // order-preserving bits (orderedBits) of the smallest and largest key

// float -> uint with the same order (negative floats reversed below the positive ones)
uint orderedBits(float x) {
  uint b = floatBitsToUint(x);
  return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}
float fromOrderedBits(uint b) { return uintBitsToFloat((b & 0x80000000u) != 0u ? b & 0x7FFFFFFFu : ~b); }

// The k-th ray of this workgroup's block; false for one outside the image or one that
// reaches nothing (an empty range or a degenerate direction).
bool blockRay(uint k, out vec3 o, out vec3 d, out vec2 range) {
  uvec2 px = gl_WorkGroupID.xy * pc.side + uvec2(k % pc.side, k / pc.side);
  o = vec3(0.0);
  d = vec3(0.0);
  range = vec2(0.0);
  if (px.x >= pc.width || px.y >= pc.height) return false;
  Ray r = rays[px.y * pc.width + px.x];
  float len = length(r.dirTmax.xyz);
  if (!(r.dirTmax.w > r.originTmin.w && len > 0.0 && !isinf(len))) return false;
  o = r.originTmin.xyz;
  d = r.dirTmax.xyz / len;
  range = vec2(r.originTmin.w, r.dirTmax.w) * len;
  return true;
}

void listIfReached(uint record, vec4 co, vec4 cd, vec2 cr, uint base) {
  vec4 sphere = spheres[record];
  if (!bundleMayReachSphere(co.xyz, cd.xyz, co.w, cd.w, cr.x, cr.y, sphere.xyz, sphere.w)) return;
  uint slot = atomicAdd(listed, 1u);
  if (pc.level == 1u && slot < kSortedMax) {
    float key = dot(sphere.xyz - co.xyz, cd.xyz);
    sortKey[slot] = key;
    sortId[slot] = record;
    atomicMin(keyLow, orderedBits(key));
    atomicMax(keyHigh, orderedBits(key));
  } else if (slot < pc.capacity) {
    candidates[base + slot] = record;
  }
}

void main() {
  uint lane = gl_LocalInvocationIndex;
  uint list = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint rayCount = pc.side * pc.side;
  // the axis: the mean origin and the normalised mean direction of the live rays
  vec3 o, d;
  vec2 range;
  vec4 sumO = vec4(0.0);
  vec3 sumD = vec3(0.0);
  for (uint k = lane; k < rayCount; k += kLanes)
    if (blockRay(k, o, d, range)) {
      sumO += vec4(o, 1.0);
      sumD += d;
    }
  partOrigin[lane] = sumO;
  partDir[lane] = sumD;
  barrier();
  if (lane == 0u) {
    vec4 so = vec4(0.0);
    vec3 sd = vec3(0.0);
    for (uint k = 0u; k < kLanes; k++) {
      so += partOrigin[k];
      sd += partDir[k];
    }
    coneEmpty = so.w == 0.0;
    // directions that cancel leave no axis: a cone that culls nothing (dirRadius 2)
    bool axis = length(sd) > 1e-6 * so.w;
    coneOrigin = vec4(so.w > 0.0 ? so.xyz / so.w : vec3(0.0), 0.0);
    coneDir = vec4(axis ? normalize(sd) : vec3(0.0, 0.0, 1.0), axis ? 0.0 : 2.0);
    listed = 0u;
    keyLow = 0xFFFFFFFFu;
    keyHigh = 0u;
  }
  if (lane < kBuckets) bucketFill[lane] = 0u;
  barrier();
  // the radii: the largest deviations from the axis
  vec4 spread = vec4(0.0, 0.0, 3.4e38, 0.0);
  for (uint k = lane; k < rayCount; k += kLanes)
    if (blockRay(k, o, d, range))
      spread = vec4(max(spread.x, length(o - coneOrigin.xyz)), max(spread.y, length(d - coneDir.xyz)), min(spread.z, range.x),
                    max(spread.w, range.y));
  partSpread[lane] = spread;
  barrier();
  if (lane == 0u) {
    vec4 s = partSpread[0];
    for (uint k = 1u; k < kLanes; k++)
      s = vec4(max(s.x, partSpread[k].x), max(s.y, partSpread[k].y), min(s.z, partSpread[k].z), max(s.w, partSpread[k].w));
    coneOrigin.w = s.x;
    coneDir.w = max(coneDir.w, s.y);
    coneRange = s.zw;
  }
  barrier();
  uint base = list * pc.capacity;
  if (!coneEmpty) {
    vec4 co = coneOrigin, cd = coneDir;
    vec2 cr = coneRange;
    uint parent = 0u, parentListed = 0xFFFFFFFFu;
    if (pc.level == 1u) {
      uvec2 block = gl_WorkGroupID.xy * pc.side / pc.parentSide;
      parent = block.y * ((pc.width + pc.parentSide - 1u) / pc.parentSide) + block.x;
      parentListed = parentCounts[parent];
    }
    if (parentListed <= pc.parentCapacity) {
      for (uint k = lane; k < parentListed; k += kLanes) listIfReached(parentLists[parent * pc.parentCapacity + k], co, cd, cr, base);
    } else {
      for (uint g = lane; g < pc.records; g += kLanes) listIfReached(g, co, cd, cr, base);
    }
  }
  barrier();
  uint n = listed;
  if (pc.level == 1u) {
    if (n <= kSortedMax && n <= pc.capacity) {
      // counting sort by bucket: count, then offsets, then scatter (O(n) and two barriers)
      float low = fromOrderedBits(keyLow), high = fromOrderedBits(keyHigh);
      float scale = high > low ? float(kBuckets) / (high - low) : 0.0;
      for (uint i = lane; i < n; i += kLanes) atomicAdd(bucketFill[min(uint((sortKey[i] - low) * scale), kBuckets - 1u)], 1u);
      barrier();
      if (lane == 0u) {
        uint sum = 0u;
        for (uint b = 0u; b < kBuckets; b++) {
          bucketStart[b] = sum;
          sum += bucketFill[b];
        }
      }
      barrier();
      for (uint i = lane; i < n; i += kLanes) {
        uint place = atomicAdd(bucketStart[min(uint((sortKey[i] - low) * scale), kBuckets - 1u)], 1u);
        candidates[base + place] = sortId[i];
      }
    } else {
      // too long to sort: the first kSortedMax as listed (the rest went straight to the list)
      for (uint i = lane; i < min(n, min(kSortedMax, pc.capacity)); i += kLanes) candidates[base + i] = sortId[i];
    }
  }
  if (lane == 0u) counts[list] = n;
}
