// A walk over a regular height grid's cells along a ray (a 2D DDA over the cells the ray
// crosses inside the grid's height range, both triangles of each tested): the closest hit
// without a BVH. Used for swapped-in grid meshes (mesh_refract.comp) and, by the compute trace
// backend, for the learned water's proxy mesh (surface_global_trace.comp). The includer defines
// vec3 positionAt(uint vertex) (xyz of vertex j * (cells.x + 1) + i).
#ifndef REFRAX_GRID_WALK_GLSL
#define REFRAX_GRID_WALK_GLSL
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

// The closest hit in [tmin, tmax) on the height grid of `cells` cells over `domain` (x0 y0 x1
// y1) whose vertices lie between heights.x and heights.y: the triangle's corners (vertex
// indices j * (cells.x + 1) + i), its cell and side (0: (a, b, d), 1: (a, d, c)), t and the
// barycentrics of its second and third corners.
bool gridHit(vec3 o, vec3 d, float tmin, float tmax, uvec2 cells, vec4 domain, vec2 heights, out uvec3 corners, out uvec2 hitCell,
             out uint side, out float t, out vec2 bary) {
  corners = uvec3(0u);
  hitCell = uvec2(0u);
  side = 0u;
  t = 0.0;
  bary = vec2(0.0);
  vec2 lo = domain.xy, hi = domain.zw;
  vec2 size = (hi - lo) / vec2(cells);
  // the part of the ray inside the grid's box (z: the height range, padded for rounding)
  float pad = 1e-5 * (1.0 + max(abs(heights.x), abs(heights.y)));
  vec3 boxLo = vec3(lo, heights.x - pad), boxHi = vec3(hi, heights.y + pad);
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
  // Every triangle is tested from where the ray enters the box, as the BVH walk does
  // (triangle_bvh.glsl): Moeller-Trumbore's t and barycentrics come from separate dot products
  // of the origin's offset from the triangle, each good to about eps |o - P0| / (s L) in
  // barycentrics (s = |cos| between ray and plane, L the triangle's size). From a camera 2.5 m
  // away that put the refracted direction, which interpolates vertex normals at the GPU's
  // barycentrics, 2.8e-5 off where the point says (s = 0.02 on 0.1 m cells); from the box
  // entry |o - P0| is the ray's path through the height range, a tenth of that or less.
  vec3 near = o + t0 * d;
  vec2 p = (near.xy - lo) / size;
  ivec2 cell = clamp(ivec2(floor(p)), ivec2(0), ivec2(cells) - 1);
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
  uint stride = cells.x + 1u;
  for (uint visits = 0u; visits < cells.x + cells.y + 1u; visits++) {
    uint a = uint(cell.y) * stride + uint(cell.x), b = a + 1u, c = a + stride, dd = c + 1u;
    vec3 A = positionAt(a), B = positionAt(b), C = positionAt(c), D = positionAt(dd);
    float th;
    vec2 bh;
    // the two triangles of grid_mesh.cpp: (a, b, d) and (a, d, c)
    if (hitTriangle(near, d, A, B, D, tmin - t0, min(best, tmax) - t0, th, bh)) {
      best = th + t0;
      corners = uvec3(a, b, dd);
      hitCell = uvec2(cell);
      side = 0u;
      bary = bh;
    }
    if (hitTriangle(near, d, A, D, C, tmin - t0, min(best, tmax) - t0, th, bh)) {
      best = th + t0;
      corners = uvec3(a, dd, c);
      hitCell = uvec2(cell);
      side = 1u;
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
    if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(cells)))) break;
  }
  t = best;
  return best < 3.4e38;
}

#endif
