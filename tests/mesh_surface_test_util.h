#pragma once
// Shared by the surface-swap tests: random meshes, rays with misses and invalid ones, and a
// run of cmdRefractThroughMesh with poisoned outputs.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "engine/surface/mesh_surface.h"
#include "engine/reference/random_rays.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"

namespace refrax::test {

// A grid with random, non-uniform column and row widths over [-1,1] x [-0.8,0.9], each vertex
// moved by up to 0.2 of its smallest neighbouring cell in x and y and given a random height,
// each cell split along a random diagonal. No normals: the surface computes area-weighted ones.
inline SurfaceMesh perturbedGridMesh(std::mt19937& rng, uint32_t cellsX, uint32_t cellsY) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  auto edges = [&](uint32_t cells, float lo, float hi) {
    std::vector<float> w(cells), e(cells + 1);
    float sum = 0;
    for (auto& x : w) sum += (x = 0.4f + 1.2f * U(rng));
    e[0] = lo;
    for (uint32_t i = 0; i < cells; i++) e[i + 1] = e[i] + (hi - lo) * w[i] / sum;
    e[cells] = hi;
    return e;
  };
  std::vector<float> xs = edges(cellsX, -1.0f, 1.0f), ys = edges(cellsY, -0.8f, 0.9f);
  SurfaceMesh m;
  for (uint32_t j = 0; j <= cellsY; j++)
    for (uint32_t i = 0; i <= cellsX; i++) {
      float hx = std::min(i > 0 ? xs[i] - xs[i - 1] : 1.0f, i < cellsX ? xs[i + 1] - xs[i] : 1.0f);
      float hy = std::min(j > 0 ? ys[j] - ys[j - 1] : 1.0f, j < cellsY ? ys[j + 1] - ys[j] : 1.0f);
      bool inner = i > 0 && i < cellsX && j > 0 && j < cellsY;
      float jx = inner ? 0.2f * hx * (2 * U(rng) - 1) : 0.0f, jy = inner ? 0.2f * hy * (2 * U(rng) - 1) : 0.0f;
      m.positions.insert(m.positions.end(), {xs[i] + jx, ys[j] + jy, 0.15f * (2 * U(rng) - 1)});
    }
  for (uint32_t j = 0; j < cellsY; j++)
    for (uint32_t i = 0; i < cellsX; i++) {
      uint32_t a = j * (cellsX + 1) + i, b = a + 1, c = a + cellsX + 1, d = c + 1;
      if (U(rng) < 0.5f) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
      else m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
    }
  return m;
}

// Separate triangles of random size, orientation and winding in [-1,1]^2 x [-0.5,0.3]: many
// steep, a fifth exactly vertical, about half facing down (back-facing for rays from above).
// Each vertex normal is its face normal tilted at random by up to ~40 degrees, so normals vary
// across a triangle and the interpolation matters.
inline SurfaceMesh triangleSoupMesh(std::mt19937& rng, uint32_t triangles) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  auto unitRandom = [&] {
    glm::dvec3 v;
    do v = glm::dvec3(2 * U(rng) - 1, 2 * U(rng) - 1, 2 * U(rng) - 1);
    while (glm::length(v) > 1 || glm::length(v) < 0.1);
    return glm::normalize(v);
  };
  SurfaceMesh m;
  for (uint32_t k = 0; k < triangles; k++) {
    glm::dvec3 c(2 * U(rng) - 1, 2 * U(rng) - 1, -0.5 + 0.8 * U(rng));
    double size = 0.1 + 0.3 * U(rng);
    glm::dvec3 p[3];
    if (k % 5 == 0) {  // vertical: two corners share x and y
      glm::dvec3 h = unitRandom();
      h.z = 0;
      h = glm::normalize(h);
      p[0] = c + size * glm::dvec3(0, 0, 0.6);
      p[1] = c - size * glm::dvec3(0, 0, 0.6);
      p[2] = c + size * (0.3 * U(rng) - 0.15) * glm::dvec3(0, 0, 1) + size * h;
    } else {
      for (auto& q : p) q = c + size * unitRandom();
    }
    glm::dvec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
    if (glm::length(face) < 0.02 * size * size) {  // too thin: try again
      k--;
      continue;
    }
    face = glm::normalize(face);
    uint32_t base = uint32_t(m.vertexCount());
    for (int q = 0; q < 3; q++) {
      glm::dvec3 n = glm::normalize(face + 0.35 * unitRandom());
      m.positions.insert(m.positions.end(), {float(p[q].x), float(p[q].y), float(p[q].z)});
      m.normals.insert(m.normals.end(), {float(n.x), float(n.y), float(n.z)});
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
  }
  return m;
}

// Rays from above towards a region a little larger than the meshes (some miss), some with
// non-unit directions (and ranges scaled to match), a few with a short range, and invalid
// ones: NaN or infinite components, a zero direction, tmax < tmin, negative tmin.
inline std::vector<GpuRay> meshTestRays(std::mt19937& rng, size_t count) {
  auto rays = ref::randomRays(rng, count, {{-1.5f, -1.5f, 0.8f}, {1.5f, 1.5f, 2.0f}, {-1.4f, -1.3f, -0.7f}, {1.4f, 1.3f, 0.4f}}, 100.0f);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < rays.size(); i++) {
    GpuRay& r = rays[i];
    if (i % 7 == 3) {  // a non-unit direction: the range is in units of its length
      float s = 0.3f + 2.7f * U(rng);
      for (float& d : r.dir) d *= s;
      r.tmax /= s;
    }
    if (i % 23 == 5) r.tmax = 0.5f + U(rng);           // may end before the surface
    if (i % 29 == 7) r.tmin = 0.5f + U(rng);           // may start past parts of it
    if (i % 13 == 11) r.dir[2] = std::fabs(r.dir[2]);  // pointing up: misses
  }
  const size_t n = rays.size();
  rays[n - 1].origin[1] = nan;
  rays[n - 2].dir[0] = nan;
  rays[n - 3].dir[0] = rays[n - 3].dir[1] = rays[n - 3].dir[2] = 0;
  rays[n - 4].origin[2] = inf;
  rays[n - 5].tmax = -1;
  rays[n - 6].tmin = -0.5f;
  rays[n - 7].dir[1] = inf;
  return rays;
}

// Rays from above aimed exactly (to float rounding) at points on the mesh's triangle edges and
// at its vertices: where a float ray query may rightly pick either neighbour, graze past a
// triangle to one behind it, or miss an outer edge (the reference's ambiguous cases).
inline std::vector<GpuRay> raysAtEdges(std::mt19937& rng, const SurfaceMesh& mesh, size_t count) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<GpuRay> rays(count);
  for (size_t i = 0; i < count; i++) {
    uint32_t tri = uint32_t(U(rng) * float(mesh.triangleCount())) % uint32_t(mesh.triangleCount());
    uint32_t e = uint32_t(3 * U(rng)) % 3;
    const float* a = &mesh.positions[3 * mesh.indices[3 * tri + e]];
    const float* b = &mesh.positions[3 * mesh.indices[3 * tri + (e + 1) % 3]];
    float s = i % 4 == 0 ? 0.0f : U(rng);  // every fourth at a vertex
    float target[3], origin[3] = {0.6f * (2 * U(rng) - 1), 0.6f * (2 * U(rng) - 1), 1.0f + U(rng)};
    float len = 0;
    for (int k = 0; k < 3; k++) {
      target[k] = a[k] + s * (b[k] - a[k]);
      origin[k] += target[k];
      len += (target[k] - origin[k]) * (target[k] - origin[k]);
    }
    len = std::sqrt(len);
    GpuRay& r = rays[i];
    for (int k = 0; k < 3; k++) {
      r.origin[k] = origin[k];
      r.dir[k] = (target[k] - origin[k]) / len;
    }
    r.tmin = 0;
    r.tmax = 100;
  }
  return rays;
}

constexpr uint32_t kMeshPoison = 0x7FC00000u;  // quiet NaN

struct MeshRun {
  std::vector<GpuRay> refracted;
  std::vector<uint32_t> flags;
};

inline MeshRun runMeshRefract(Context& ctx, const MeshSurface& mesh, const std::vector<GpuRay>& rays, float ior) {
  uint32_t n = uint32_t(rays.size());
  Buffer in = createBufferFrom(ctx, rays);
  Buffer out = createBuffer(ctx, rays.size() * sizeof(GpuRay));
  Buffer flags = createBuffer(ctx, rays.size() * 4);
  fillBuffer(ctx, out, kMeshPoison);
  fillBuffer(ctx, flags, kMeshPoison);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRefractThroughMesh(cb, mesh, in, n, ior, out, flags); });
  return {downloadVector<GpuRay>(ctx, out, n), downloadVector<uint32_t>(ctx, flags, n)};
}

}  // namespace refrax::test
