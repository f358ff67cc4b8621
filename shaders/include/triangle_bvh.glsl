// The closest triangle along a ray through a triangle BVH (engine/trace/box_bvh.h, leaf k = triangle
// k): the compute trace backend's stand-in for a ray query's closest hit. The includer declares
// bvhNodes (box_bvh.glsl), indices[] (3 per triangle) and vec3 positionAt(uint vertex).
#ifndef REFRAX_TRIANGLE_BVH_GLSL
#define REFRAX_TRIANGLE_BVH_GLSL

// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013), as ray-query drivers
// compute it: the triangle is sheared into the ray's frame and tested by 2D edge functions, so
// a ray through a shared edge hits exactly one of the two triangles, and the barycentrics keep
// float accuracy on small steep triangles where Moeller-Trumbore's lost a few digits (the
// refracted direction interpolates vertex normals that differ a lot across them).
bool hitTriangleWatertight(vec3 o, vec3 d, vec3 P0, vec3 P1, vec3 P2, float tmin, float tbest, out float t, out vec2 bary) {
  t = 0.0;
  bary = vec2(0.0);
  vec3 ad = abs(d);
  int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (d[kz] < 0.0) {  // keep the winding
    int s = kx;
    kx = ky;
    ky = s;
  }
  float sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  vec3 A = P0 - o, B = P1 - o, C = P2 - o;
  float ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
  float bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
  float cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
  float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  float det = u + v + w;
  if (det == 0.0) return false;
  float T = (u * sz * A[kz] + v * sz * B[kz] + w * sz * C[kz]) / det;
  if (!(T >= tmin && T < tbest)) return false;
  t = T;
  bary = vec2(v, w) / det;  // the weights of P1 and P2
  return true;
}
// The closest triangle in [tmin, tmax) through the triangle BVH: its index, t and barycentrics.
bool bvhClosestTriangle(vec3 o, vec3 d, float tmin, float tmax, out uint tri, out float t, out vec2 bary) {
  tri = 0u;
  t = 0.0;
  bary = vec2(0.0);
  vec3 invD = vec3(1.0) / d;
  // Every triangle is tested from one origin, where the ray enters the whole mesh's box: near
  // the triangles (float keeps more of the hit's digits than from a far camera) and the same
  // ray for all of them (watertight along shared edges).
  float shift;
  BvhNode root = bvhNodes[0];
  if (!bvhBoxHit(root.lo, root.hi, o, invD, tmin, tmax, shift)) return false;
  vec3 near = o + shift * d;
  float best = tmax - shift;
  bool found = false;
  uint stack[kBvhStack];
  int sp = 0;
  stack[sp++] = 0u;
  while (sp > 0) {
    BvhNode node = bvhNodes[stack[--sp]];
    if (!bvhBoxHit(node.lo, node.hi, near, invD, tmin - shift, best)) continue;
    if (node.left != kBvhLeaf) {
      stack[sp++] = node.right;
      stack[sp++] = node.left;
      continue;
    }
    uint k = node.right;
    float th;
    vec2 bh;
    if (hitTriangleWatertight(near, d, positionAt(indices[3 * k]), positionAt(indices[3 * k + 1]), positionAt(indices[3 * k + 2]),
                              tmin - shift, best, th, bh)) {
      best = th;
      tri = k;
      t = th + shift;
      bary = bh;
      found = true;
    }
  }
  return found;
}
#endif
