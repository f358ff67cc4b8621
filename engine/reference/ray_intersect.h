#pragma once
// CPU double-precision references for ray-primitive tests (Moller-Trumbore, slab test).
// Independent of the shaders; used by tests and by `refrax selftest`.
#include <glm/glm.hpp>

namespace refrax::ref {

struct TriangleHitD {
  bool hit = false;
  double t = 0, u = 0, v = 0;
};

// Two-sided Moller-Trumbore; hit only for t in [tmin, tmax].
inline TriangleHitD intersectTriangle(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& p0, const glm::dvec3& p1,
                                      const glm::dvec3& p2, double tmin, double tmax) {
  TriangleHitD h;
  glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
  double det = glm::dot(e1, pv);
  if (det == 0.0) return h;
  double inv = 1.0 / det;
  glm::dvec3 tv = o - p0;
  double u = glm::dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0) return h;
  glm::dvec3 qv = glm::cross(tv, e1);
  double v = glm::dot(d, qv) * inv;
  if (v < 0.0 || u + v > 1.0) return h;
  double t = glm::dot(e2, qv) * inv;
  if (t < tmin || t > tmax) return h;
  h.hit = true;
  h.t = t;
  h.u = u;
  h.v = v;
  return h;
}

// Barycentrics (u, v) of the point where the ray meets the triangle's plane, unclamped:
// negative values say how far outside an edge it passes (false when parallel).
inline bool planeBarycentrics(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& p0, const glm::dvec3& p1,
                              const glm::dvec3& p2, double& u, double& v) {
  glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
  double det = glm::dot(e1, pv);
  if (det == 0.0) return false;
  glm::dvec3 tv = o - p0;
  u = glm::dot(tv, pv) / det;
  v = glm::dot(d, glm::cross(tv, e1)) / det;
  return true;
}

// Does the segment o + t d, t in [tmin, tmax], touch the closed box [lo, hi]?
inline bool overlapsBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi, double tmin,
                        double tmax) {
  for (int a = 0; a < 3; a++) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    tmin = std::max(tmin, t0);
    tmax = std::min(tmax, t1);
    if (tmin > tmax) return false;
  }
  return true;
}

}  // namespace refrax::ref
