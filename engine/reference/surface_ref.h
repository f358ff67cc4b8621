#pragma once
// CPU double-precision reference of the water-surface stage (engine/surface/water_surface.h): the
// same lattice, child choice, normals and Snell's law (shared with the shaders through
// engine/surface/surface_math.h), with H called directly in double instead of through a hash table.
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/trace/rays.h"
#include "engine/surface/water_surface.h"

namespace refrax::ref {

using HeightFunction = std::function<double(double x, double y)>;

struct SurfaceTriangle {
  uint32_t level = 0;
  int i = 0, j = 0, side = 0;
  bool operator==(const SurfaceTriangle& o) const { return level == o.level && i == o.i && j == o.j && side == o.side; }
};

struct SurfaceRefHit {
  uint32_t flags = 0;  // kSurfaceHit, kSurfaceMissed, ... (engine/surface/surface_record.h)
  SurfaceTriangle tri;
  double t = 0, u = 0, v = 0;
  glm::dvec3 p{0}, n{0}, w{0};  // hit point, normal facing the ray, refracted direction
  glm::dvec3 vertexNormals[3];  // raw (unnormalised) normals of the triangle's corners
  // Smallest barycentric margin of the triangle chosen at any level (global and children):
  // near 0, a float tracer may rightly choose the neighbour.
  double margin = 0;
};

// The coarse heights, evaluated once per surface.
struct SurfaceRef {
  WaterSurfaceConfig config;
  HeightFunction height;
  double hx = 0, hy = 0;  // finest spacing
  std::vector<double> coarse;  // (cellsX + 1) x (cellsY + 1) interior vertices
  double zmin = 0, zmax = 0;
};
SurfaceRef makeSurfaceRef(const WaterSurfaceConfig& config, const HeightFunction& height);

// Finest-lattice point (X, Y) in world xy.
glm::dvec2 latticePointRef(const SurfaceRef& s, int X, int Y);

// Whole stage for one ray: global search over the coarse mesh, K subdivision levels,
// refraction.
SurfaceRefHit traceSurfaceRef(const SurfaceRef& s, const GpuRay& ray);

// Refraction on a given finest triangle (the discrete choices held fixed), heights from
// `height` (which may differ from s.height, e.g. perturbed weights).
SurfaceRefHit refractOnTriangleRef(const SurfaceRef& s, const HeightFunction& height, const GpuRay& ray, const SurfaceTriangle& tri);

// dLoss/dz of every finest-lattice point (X, Y) that refractOnTriangleRef reads, for
// dLoss/dp = gp and dLoss/dw = gw.
std::map<std::pair<int, int>, double> surfaceBackwardRef(const SurfaceRef& s, const GpuRay& ray, const SurfaceTriangle& tri,
                                                         const glm::dvec3& gp, const glm::dvec3& gw);

// The finest triangle a GPU record names.
SurfaceTriangle triangleOf(const SurfaceRecord& rec);

}  // namespace refrax::ref
