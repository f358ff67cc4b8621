#include "engine/synth/triangle_bvh.h"

#include <algorithm>
#include <cmath>

namespace refrax::synth {

namespace {

struct BuildState {
  TriangleBvh& bvh;
  std::vector<glm::dvec3> centroids;
};

int buildNode(BuildState& st, int first, int count) {
  int index = int(st.bvh.nodes.size());
  st.bvh.nodes.push_back({});
  glm::dvec3 lo(1e300), hi(-1e300), clo(1e300), chi(-1e300);
  for (int i = first; i < first + count; i++) {
    const MeshTriangle& t = st.bvh.triangles[st.bvh.order[i]];
    for (const auto& p : t.p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    clo = glm::min(clo, st.centroids[st.bvh.order[i]]);
    chi = glm::max(chi, st.centroids[st.bvh.order[i]]);
  }
  if (count <= 4) {
    st.bvh.nodes[index] = {lo, hi, first, count, -1};
    return index;
  }
  glm::dvec3 extent = chi - clo;
  int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  int half = count / 2;
  auto begin = st.bvh.order.begin() + first;
  // Ties broken by index so the tree does not depend on the sort implementation's choices.
  std::nth_element(begin, begin + half, begin + count, [&](int a, int b) {
    double ca = st.centroids[a][axis], cb = st.centroids[b][axis];
    return ca < cb || (ca == cb && a < b);
  });
  int left = buildNode(st, first, half);
  int right = buildNode(st, first + half, count - half);
  st.bvh.nodes[index] = {lo, hi, left, 0, right};
  return index;
}

bool hitBox(const BvhNode& n, const glm::dvec3& o, const glm::dvec3& invD, double tMin, double tMax, double& tEnter) {
  for (int a = 0; a < 3; a++) {
    double t0 = (n.lo[a] - o[a]) * invD[a], t1 = (n.hi[a] - o[a]) * invD[a];
    if (t0 > t1) std::swap(t0, t1);
    // NaN (0 * inf on a slab face) must not shrink the interval.
    if (t0 > tMin) tMin = t0;
    if (t1 < tMax) tMax = t1;
    if (tMin > tMax) return false;
  }
  tEnter = tMin;
  return true;
}

}  // namespace

TriangleBvh buildTriangleBvh(std::vector<MeshTriangle> triangles) {
  TriangleBvh bvh;
  bvh.triangles = std::move(triangles);
  bvh.order.resize(bvh.triangles.size());
  for (size_t i = 0; i < bvh.order.size(); i++) bvh.order[i] = int(i);
  if (bvh.triangles.empty()) return bvh;
  BuildState st{bvh, {}};
  for (const auto& t : bvh.triangles) st.centroids.push_back((t.p[0] + t.p[1] + t.p[2]) / 3.0);
  buildNode(st, 0, int(bvh.triangles.size()));
  return bvh;
}

std::optional<TriangleHit> intersectTriangle(const MeshTriangle& tri, const glm::dvec3& o, const glm::dvec3& d, double tMin, double tMax) {
  glm::dvec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
  glm::dvec3 pv = glm::cross(d, e2);
  double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-300) return std::nullopt;
  double inv = 1.0 / det;
  glm::dvec3 tv = o - tri.p[0];
  double b1 = glm::dot(tv, pv) * inv;
  if (b1 < 0 || b1 > 1) return std::nullopt;
  glm::dvec3 qv = glm::cross(tv, e1);
  double b2 = glm::dot(d, qv) * inv;
  if (b2 < 0 || b1 + b2 > 1) return std::nullopt;
  double t = glm::dot(e2, qv) * inv;
  if (!(t > tMin && t < tMax)) return std::nullopt;
  return TriangleHit{t, -1, b1, b2};
}

std::optional<TriangleHit> closestTriangleHit(const TriangleBvh& bvh, const glm::dvec3& o, const glm::dvec3& d, double tMin, double tMax) {
  if (bvh.nodes.empty()) return std::nullopt;
  glm::dvec3 invD(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
  std::optional<TriangleHit> best;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& n = bvh.nodes[stack[--top]];
    double tEnter;
    if (!hitBox(n, o, invD, tMin, tMax, tEnter)) continue;
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; i++) {
        auto h = intersectTriangle(bvh.triangles[bvh.order[i]], o, d, tMin, tMax);
        if (h) {
          h->triangle = bvh.order[i];
          tMax = h->t;
          best = h;
        }
      }
    } else {
      stack[top++] = n.first;
      stack[top++] = n.right;
    }
  }
  return best;
}

}  // namespace refrax::synth
