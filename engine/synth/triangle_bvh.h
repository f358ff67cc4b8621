#pragma once
// CPU triangle mesh with a bounding volume hierarchy, for the synthetic data generator's
// scene under the water (independent of the trainer's Vulkan acceleration structures).
#include <glm/glm.hpp>
#include <optional>
#include <vector>

namespace refrax::synth {

struct MeshTriangle {
  glm::dvec3 p[3];
  glm::dvec3 n[3];   // shading normals per corner
  glm::dvec2 uv[3];
  int material = 0;
};

struct TriangleHit {
  double t;
  int triangle;
  double b1, b2;  // barycentric weights of corners 1 and 2
};

struct BvhNode {
  glm::dvec3 lo, hi;
  int first;  // leaf: first index into order; inner: index of the left child
  int count;  // leaf: triangle count; inner: 0
  int right;  // inner: index of the right child
};

struct TriangleBvh {
  std::vector<MeshTriangle> triangles;
  std::vector<BvhNode> nodes;
  std::vector<int> order;
};

// Median split on the longest centroid axis, at most 4 triangles per leaf.
TriangleBvh buildTriangleBvh(std::vector<MeshTriangle> triangles);
// Closest hit with t in (tMin, tMax); both faces count.
std::optional<TriangleHit> closestTriangleHit(const TriangleBvh& bvh, const glm::dvec3& o, const glm::dvec3& d, double tMin, double tMax);
// Möller-Trumbore; exposed for tests.
std::optional<TriangleHit> intersectTriangle(const MeshTriangle& tri, const glm::dvec3& o, const glm::dvec3& d, double tMin, double tMax);

}  // namespace refrax::synth
