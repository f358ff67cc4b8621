#include "engine/surface/mesh_surface.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/trace/presort.h"
#include "engine/trace/triangle_bvh.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

struct MeshRefractPush {
  uint32_t count;
  float eta;
  uint32_t cells[2];
  float domain[4];
  float heights[2];
};

// The mesh is the grid: its vertex count and every vertex's x and y (as makeGridMesh places
// them, to float rounding).
void checkGrid(const SurfaceMesh& mesh, const HeightGridLayout& g) {
  const std::string what = "surface mesh: not the stated height grid: ";
  if (g.cellsX == 0 || g.cellsY == 0 || !(g.x1 > g.x0) || !(g.y1 > g.y0)) fail(what + "no cells or an empty domain");
  if (mesh.vertexCount() != size_t(g.cellsX + 1) * (g.cellsY + 1))
    fail(what + std::to_string(mesh.vertexCount()) + " vertices for " + std::to_string(g.cellsX) + "x" + std::to_string(g.cellsY) + " cells");
  float tolerance = 1e-5f * std::max({std::abs(g.x0), std::abs(g.x1), std::abs(g.y0), std::abs(g.y1), 1.0f});
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) {
      const float* p = &mesh.positions[3 * (size_t(j) * (g.cellsX + 1) + i)];
      float x = g.x0 + (g.x1 - g.x0) * float(i) / float(g.cellsX), y = g.y0 + (g.y1 - g.y0) * float(j) / float(g.cellsY);
      if (std::abs(p[0] - x) > tolerance || std::abs(p[1] - y) > tolerance)
        fail(what + "vertex (" + std::to_string(i) + ", " + std::to_string(j) + ") is not on the lattice");
    }
}

void checkMesh(const SurfaceMesh& mesh) {
  const std::string what = "surface mesh: ";
  if (mesh.positions.empty() || mesh.positions.size() % 3 != 0) fail(what + "no vertices (or a position count that is not a multiple of 3)");
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) fail(what + "no triangles (or an index count that is not a multiple of 3)");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    fail(what + std::to_string(mesh.normals.size() / 3) + " normals for " + std::to_string(mesh.vertexCount()) + " vertices");
  if (mesh.vertexCount() > (size_t(1) << 31) || mesh.triangleCount() > (size_t(1) << 31)) fail(what + "too many vertices or triangles");
  for (size_t i = 0; i < mesh.positions.size(); i++)
    if (!std::isfinite(mesh.positions[i])) fail(what + "vertex " + std::to_string(i / 3) + " has a non-finite position");
  for (size_t i = 0; i < mesh.indices.size(); i++)
    if (mesh.indices[i] >= mesh.vertexCount())
      fail(what + "triangle " + std::to_string(i / 3) + " names vertex " + std::to_string(mesh.indices[i]) + " of " +
           std::to_string(mesh.vertexCount()));
}

// The triangles (index triples) in the order the BLAS gets them: lavapipe's builder splits
// the input order at its middle, so a file's arbitrary order is replaced by a median split
// of the triangles' boxes (engine/trace/presort.h). The shader reads the triples by primitive
// index from this same list, so the order is invisible outside.
std::vector<uint32_t> triangleBuildOrder(const SurfaceMesh& mesh) { return trianglesInSplitOrder(mesh.positions, mesh.indices); }

}  // namespace

std::vector<float> meshUnitNormals(const SurfaceMesh& mesh) {
  checkMesh(mesh);
  if (mesh.normals.empty()) return vertexNormals(mesh.positions, mesh.indices);
  std::vector<float> n(mesh.normals.size());
  for (size_t i = 0; i < n.size(); i += 3) {
    float x = mesh.normals[i], y = mesh.normals[i + 1], z = mesh.normals[i + 2];
    float len = std::sqrt(x * x + y * y + z * z);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !(len > 0.0f) || !std::isfinite(len))
      fail("surface mesh: the normal of vertex " + std::to_string(i / 3) + " is zero or not finite");
    n[i] = x / len;
    n[i + 1] = y / len;
    n[i + 2] = z / len;
  }
  return n;
}

MeshSurface createMeshSurface(Context& ctx, const SurfaceMesh& mesh, const HeightGridLayout* grid) {
  std::vector<float> normals = meshUnitNormals(mesh);  // validates
  MeshSurface m;
  if (grid) {
    checkGrid(mesh, *grid);
    m.walkGrid = true;
    m.grid = *grid;
    m.zMin = INFINITY;
    m.zMax = -INFINITY;
    for (size_t i = 2; i < mesh.positions.size(); i += 3) {
      m.zMin = std::min(m.zMin, mesh.positions[i]);
      m.zMax = std::max(m.zMax, mesh.positions[i]);
    }
  }
  m.vertexCount = uint32_t(mesh.vertexCount());
  m.triangleCount = uint32_t(mesh.triangleCount());
  m.positions = createBufferFrom(ctx, mesh.positions, kAccelInput);
  m.normals = createBufferFrom(ctx, normals);
  const std::vector<uint32_t> ordered = triangleBuildOrder(mesh);
  m.indices = createBufferFrom(ctx, ordered, kAccelInput);
  auto B = kStorageBuffer;
  if (ctx.trace == TraceBackend::Compute) {
    // (a grid walks its cells: its tree is never read, but binding 0 needs a buffer)
    m.bvh = createTriangleBvh(ctx, mesh.positions, m.walkGrid ? std::vector<uint32_t>(ordered.begin(), ordered.begin() + 3) : ordered);
    m.refract = createComputePipeline(ctx, "mesh_refract_compute", {B, B, B, B, B, B, B}, sizeof(MeshRefractPush), {{0, m.walkGrid ? 1u : 0u}});
  } else {
    m.blas = createTriangleBlas(ctx, m.positions, m.vertexCount, 12, m.indices, m.triangleCount);
    m.top = createTopLevel(ctx, {makeInstance(m.blas, 0)});
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cmdBuild(cb, m.blas);
      cmdBarrier(cb);
      cmdBuild(cb, m.top.tlas);
    });
    m.refract = createComputePipeline(ctx, "mesh_refract", {kAccelStruct, B, B, B, B, B, B}, sizeof(MeshRefractPush),
                                      {{0, m.walkGrid ? 1u : 0u}});
  }
  m.built = true;
  return m;
}

void cmdRefractThroughMesh(VkCommandBuffer cb, const MeshSurface& mesh, const Buffer& rays, uint32_t count, float ior,
                           const Buffer& refracted, const Buffer& flags) {
  if (count == 0) return;
  if (!(ior > 0.0f) || !std::isfinite(ior)) fail("surface mesh: the IOR must be a positive number");
  if (!mesh.built) fail("surface mesh: not built (use createMeshSurface)");
  if (rays.size < VkDeviceSize(count) * sizeof(GpuRay) || refracted.size < VkDeviceSize(count) * sizeof(GpuRay) ||
      flags.size < VkDeviceSize(count) * 4)
    fail("surface mesh: the ray, refracted-ray or flag buffer is too small for " + std::to_string(count) + " rays");
  MeshRefractPush push{count, 1.0f / ior, {mesh.grid.cellsX, mesh.grid.cellsY}, {mesh.grid.x0, mesh.grid.y0, mesh.grid.x1, mesh.grid.y1},
                       {mesh.zMin, mesh.zMax}};
  cmdBarrier(cb);
  cmdDispatch(cb, mesh.refract,
              {mesh.bvh.leaves ? bind(mesh.bvh.nodes) : bind(mesh.top.tlas), bind(rays), bind(mesh.positions), bind(mesh.normals),
               bind(mesh.indices), bind(refracted), bind(flags)},
              &push, groupsFor(count, 64));
}

SurfaceMesh bakeHeightMesh(Context& ctx, const HeightSource& heights, const SurfaceDomain& domain, uint32_t cellsX, uint32_t cellsY) {
  if (cellsX == 0 || cellsY == 0) fail("surface bake: needs at least one cell in each direction");
  if ((uint64_t(cellsX) + 1) * (uint64_t(cellsY) + 1) > (uint64_t(1) << 26)) fail("surface bake: more than 2^26 lattice points");
  if (!std::isfinite(domain.x0) || !std::isfinite(domain.y0) || !std::isfinite(domain.x1) || !std::isfinite(domain.y1) ||
      !(domain.x1 > domain.x0) || !(domain.y1 > domain.y0))
    fail("surface bake: the domain is empty, inverted or not finite");
  GridMesh grid = makeGridMesh(cellsX, cellsY, domain.x0, domain.y0, domain.x1, domain.y1);
  const uint32_t n = grid.vertexCount();
  std::vector<float> xy(size_t(n) * 2);
  for (size_t i = 0; i < n; i++) {
    xy[2 * i] = grid.vertices[3 * i];
    xy[2 * i + 1] = grid.vertices[3 * i + 1];
  }
  Buffer points = createBufferFrom(ctx, xy);
  Buffer z = createBuffer(ctx, VkDeviceSize(n) * 4);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { heights.evaluate(cb, points, n, z); });
  std::vector<float> h = downloadVector<float>(ctx, z, n);
  for (size_t i = 0; i < n; i++) {
    if (!std::isfinite(h[i]))
      fail("surface bake: the height at (" + std::to_string(xy[2 * i]) + ", " + std::to_string(xy[2 * i + 1]) + ") is not finite");
    grid.vertices[3 * i + 2] = h[i];
  }
  return surfaceMeshFromGrid(grid);
}

}  // namespace refrax
