#include "engine/synth/scene_builder.h"

#include <algorithm>
#include <cmath>

namespace refrax::synth {

namespace {
constexpr double kPi = 3.14159265358979323846;

MeshTriangle makeTriangle(const glm::dvec3 p[3], const glm::dvec3 n[3], const glm::dvec2 uv[3], int material) {
  MeshTriangle t;
  for (int i = 0; i < 3; i++) {
    t.p[i] = p[i];
    t.n[i] = n[i];
    t.uv[i] = uv[i];
  }
  t.material = material;
  return t;
}
}  // namespace

void SceneBuilder::quad(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d, int material) {
  // a b c d counter-clockwise; UV (0,0) (1,0) (1,1) (0,1).
  glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
  glm::dvec3 ns[3] = {n, n, n};
  glm::dvec3 p0[3] = {a, b, c}, p1[3] = {a, c, d};
  glm::dvec2 uv0[3] = {{0, 0}, {1, 0}, {1, 1}}, uv1[3] = {{0, 0}, {1, 1}, {0, 1}};
  triangles.push_back(makeTriangle(p0, ns, uv0, material));
  triangles.push_back(makeTriangle(p1, ns, uv1, material));
}

void SceneBuilder::floorRect(double xmin, double ymin, double xmax, double ymax, double z, int material) {
  quad({xmin, ymin, z}, {xmax, ymin, z}, {xmax, ymax, z}, {xmin, ymax, z}, material);
}

void SceneBuilder::box(const glm::dvec3& centre, const glm::dvec3& half, double yaw, int material, int topMaterial) {
  double c = std::cos(yaw), s = std::sin(yaw);
  auto corner = [&](double sx, double sy, double sz) {
    double x = sx * half.x, y = sy * half.y;
    return centre + glm::dvec3(c * x - s * y, s * x + c * y, sz * half.z);
  };
  glm::dvec3 p[8];
  for (int i = 0; i < 8; i++) p[i] = corner(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  int top = topMaterial >= 0 ? topMaterial : material;
  quad(p[4], p[5], p[7], p[6], top);       // +Z
  quad(p[0], p[2], p[3], p[1], material);  // -Z
  quad(p[0], p[1], p[5], p[4], material);  // -Y
  quad(p[3], p[2], p[6], p[7], material);  // +Y
  quad(p[1], p[3], p[7], p[5], material);  // +X
  quad(p[2], p[0], p[4], p[6], material);  // -X
}

void SceneBuilder::sphere(const glm::dvec3& centre, double radius, int material, int segments) {
  int rings = std::max(2, segments / 2);
  auto point = [&](int i, int j, glm::dvec3& n, glm::dvec2& uv) {
    double phi = 2 * kPi * i / segments, theta = kPi * j / rings;
    n = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
    uv = {double(i) / segments, 1.0 - double(j) / rings};
    return centre + radius * n;
  };
  for (int j = 0; j < rings; j++)
    for (int i = 0; i < segments; i++) {
      glm::dvec3 n[4], p[4];
      glm::dvec2 uv[4];
      p[0] = point(i, j, n[0], uv[0]);
      p[1] = point(i, j + 1, n[1], uv[1]);
      p[2] = point(i + 1, j + 1, n[2], uv[2]);
      p[3] = point(i + 1, j, n[3], uv[3]);
      if (j > 0) {
        glm::dvec3 pa[3] = {p[0], p[1], p[3]}, na[3] = {n[0], n[1], n[3]};
        glm::dvec2 ua[3] = {uv[0], uv[1], uv[3]};
        triangles.push_back(makeTriangle(pa, na, ua, material));
      }
      if (j < rings - 1) {
        glm::dvec3 pb[3] = {p[1], p[2], p[3]}, nb[3] = {n[1], n[2], n[3]};
        glm::dvec2 ub[3] = {uv[1], uv[2], uv[3]};
        triangles.push_back(makeTriangle(pb, nb, ub, material));
      }
    }
}

void SceneBuilder::cylinder(const glm::dvec3& base, double radius, double height, int material, int segments, int capMaterial) {
  int cap = capMaterial >= 0 ? capMaterial : material;
  glm::dvec3 up(0, 0, 1), down(0, 0, -1);
  for (int i = 0; i < segments; i++) {
    double a0 = 2 * kPi * i / segments, a1 = 2 * kPi * (i + 1) / segments;
    glm::dvec3 r0(std::cos(a0), std::sin(a0), 0), r1(std::cos(a1), std::sin(a1), 0);
    glm::dvec3 b0 = base + radius * r0, b1 = base + radius * r1, t0 = b0 + height * up, t1 = b1 + height * up;
    double u0 = double(i) / segments, u1 = double(i + 1) / segments;
    glm::dvec3 pa[3] = {b0, b1, t1}, na[3] = {r0, r1, r1};
    glm::dvec2 ua[3] = {{u0, 0}, {u1, 0}, {u1, 1}};
    triangles.push_back(makeTriangle(pa, na, ua, material));
    glm::dvec3 pb[3] = {b0, t1, t0}, nb[3] = {r0, r1, r0};
    glm::dvec2 ub[3] = {{u0, 0}, {u1, 1}, {u0, 1}};
    triangles.push_back(makeTriangle(pb, nb, ub, material));
    // Caps: planar UV mapping of the disc onto the unit square.
    glm::dvec3 tc = base + height * up;
    glm::dvec2 cu = {0.5, 0.5}, cu0 = cu + 0.5 * glm::dvec2(r0), cu1 = cu + 0.5 * glm::dvec2(r1);
    glm::dvec3 pt[3] = {tc, t0, t1}, nt[3] = {up, up, up};
    glm::dvec2 ut[3] = {cu, cu0, cu1};
    triangles.push_back(makeTriangle(pt, nt, ut, cap));
    glm::dvec3 pd[3] = {base, b1, b0}, nd[3] = {down, down, down};
    glm::dvec2 ud[3] = {cu, cu1, cu0};
    triangles.push_back(makeTriangle(pd, nd, ud, cap));
  }
}

}  // namespace refrax::synth
