#include "engine/reference/surface_ref.h"

#include <algorithm>
#include <cmath>

#include "engine/reference/ray_intersect.h"
#include "engine/surface/surface_math.h"

namespace refrax::ref {

namespace {

using glm::dvec3;

struct LoadedRay {
  bool valid = false;
  dvec3 o{0}, d{0};
  double tmin = 0, tmax = 0;
};

// As loadRay in shaders/include/surface_lattice.glsl: unit direction, tmin/tmax rescaled.
LoadedRay loadRayRef(const GpuRay& r) {
  LoadedRay l;
  l.o = dvec3(r.origin[0], r.origin[1], r.origin[2]);
  dvec3 d(r.dir[0], r.dir[1], r.dir[2]);
  double len = glm::length(d);
  bool finite = std::isfinite(r.origin[0]) && std::isfinite(r.origin[1]) && std::isfinite(r.origin[2]) && std::isfinite(r.tmin) &&
                std::isfinite(r.dir[0]) && std::isfinite(r.dir[1]) && std::isfinite(r.dir[2]) && std::isfinite(r.tmax);
  if (!finite || !(len > 0)) return l;
  l.d = d / len;
  l.tmin = double(r.tmin) * len;
  l.tmax = double(r.tmax) * len;
  l.valid = l.tmin >= 0 && l.tmax >= l.tmin;
  return l;
}

dvec3 vertexAt(const SurfaceRef& s, const HeightFunction& h, int X, int Y) {
  glm::dvec2 xy = latticePointRef(s, X, Y);
  return dvec3(xy.x, xy.y, h(xy.x, xy.y));
}

void finestCorner(const SurfaceRef& s, const SurfaceTriangle& tri, int corner, int& X, int& Y) {
  int vi, vj;
  f64::triangleCorner(tri.i, tri.j, tri.side, corner, vi, vj);
  int shift = int(s.config.subdivisionLevels - tri.level);
  X = vi << shift;
  Y = vj << shift;
}

dvec3 vertexNormalRef(const SurfaceRef& s, const HeightFunction& h, int X, int Y) {
  double z[6];
  for (int k = 0; k < 6; k++) {
    int di, dj;
    f64::ringOffset(k, di, dj);
    z[k] = vertexAt(s, h, X + di, Y + dj).z;
  }
  return f64::vertexNormalRaw(z[0], z[1], z[2], z[3], z[4], z[5], s.hx, s.hy);
}

double margin(double u, double v) { return std::min({u, v, 1 - u - v}); }

}  // namespace

SurfaceRef makeSurfaceRef(const WaterSurfaceConfig& config, const HeightFunction& height) {
  SurfaceRef s;
  s.config = config;
  s.height = height;
  const uint32_t K = config.subdivisionLevels, n = config.gridCells;
  s.hx = (double(config.domain.x1) - config.domain.x0) / double(n << K);
  s.hy = (double(config.domain.y1) - config.domain.y0) / double(n << K);
  s.coarse.resize(size_t(n + 1) * (n + 1));
  s.zmin = INFINITY;
  s.zmax = -INFINITY;
  for (uint32_t j = 0; j <= n; j++)
    for (uint32_t i = 0; i <= n; i++) {
      double z = vertexAt(s, height, int(i << K), int(j << K)).z;
      s.coarse[size_t(j) * (n + 1) + i] = z;
      s.zmin = std::min(s.zmin, z);
      s.zmax = std::max(s.zmax, z);
    }
  return s;
}

glm::dvec2 latticePointRef(const SurfaceRef& s, int X, int Y) {
  return {double(s.config.domain.x0) + X * s.hx, double(s.config.domain.y0) + Y * s.hy};
}

SurfaceTriangle triangleOf(const SurfaceRecord& rec) {
  return {surfaceRecordLevel(rec), int(surfaceRecordCellI(rec)), int(surfaceRecordCellJ(rec)), int(surfaceRecordSide(rec))};
}

SurfaceRefHit traceSurfaceRef(const SurfaceRef& s, const GpuRay& ray) {
  SurfaceRefHit hit;
  LoadedRay r = loadRayRef(ray);
  if (!r.valid) {
    hit.flags = kSurfaceInvalidRay;
    return hit;
  }
  // Global search: only cells under the part of the ray within the surface's z range.
  const uint32_t K = s.config.subdivisionLevels, n = s.config.gridCells;
  double t0 = r.tmin, t1 = r.tmax, pad = 1e-6 * (1 + std::abs(s.zmax) + std::abs(s.zmin));
  if (std::abs(r.d.z) > 0) {
    double ta = (s.zmin - pad - r.o.z) / r.d.z, tb = (s.zmax + pad - r.o.z) / r.d.z;
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  } else if (r.o.z < s.zmin - pad || r.o.z > s.zmax + pad) {
    t1 = -1;
  }
  TriangleHitD best;
  SurfaceTriangle bestTri;
  if (t1 >= t0) {
    double hxc = s.hx * double(1u << K), hyc = s.hy * double(1u << K);
    dvec3 a = r.o + t0 * r.d, b = r.o + t1 * r.d;
    auto cellRange = [&](double lo, double hi, double origin, double h, int& c0, int& c1) {
      c0 = std::max(0, int(std::floor((lo - origin) / h)) - 1);
      c1 = std::min(int(n) - 1, int(std::floor((hi - origin) / h)) + 1);
    };
    int i0, i1, j0, j1;
    cellRange(std::min(a.x, b.x), std::max(a.x, b.x), s.config.domain.x0, hxc, i0, i1);
    cellRange(std::min(a.y, b.y), std::max(a.y, b.y), s.config.domain.y0, hyc, j0, j1);
    for (int j = j0; j <= j1; j++)
      for (int i = i0; i <= i1; i++)
        for (int side = 0; side < 2; side++) {
          SurfaceTriangle tri{0, i, j, side};
          dvec3 P[3];
          for (int c = 0; c < 3; c++) {
            int vi, vj;
            f64::triangleCorner(i, j, side, c, vi, vj);
            glm::dvec2 xy = latticePointRef(s, vi << K, vj << K);
            P[c] = dvec3(xy.x, xy.y, s.coarse[size_t(vj) * (n + 1) + vi]);
          }
          TriangleHitD h = intersectTriangle(r.o, r.d, P[0], P[1], P[2], r.tmin, r.tmax);
          if (h.hit && (!best.hit || h.t < best.t)) {
            best = h;
            bestTri = tri;
          }
        }
  }
  if (!best.hit) {
    hit.flags = kSurfaceMissed;
    return hit;
  }
  hit.flags = kSurfaceHit;
  hit.margin = margin(best.u, best.v);
  SurfaceTriangle tri = bestTri;
  for (uint32_t k = 1; k <= K; k++) {
    int bestInside = -1, bestOutside = -1;
    double bestT = 0, bestOut = 0;
    dvec3 tuvs[4];
    SurfaceTriangle children[4];
    for (int c = 0; c < 4; c++) {
      SurfaceTriangle ch;
      ch.level = k;
      f64::childTriangle(tri.i, tri.j, tri.side, c, ch.i, ch.j, ch.side);
      children[c] = ch;
      dvec3 P[3];
      for (int q = 0; q < 3; q++) {
        int X, Y;
        finestCorner(s, ch, q, X, Y);
        P[q] = vertexAt(s, s.height, X, Y);
      }
      bool ok = f64::rayTrianglePlane(r.o, r.d, P[0], P[1], P[2], 1e-6, tuvs[c]);
      f64::considerChild(c, ok, tuvs[c], r.tmin, r.tmax, bestInside, bestT, bestOutside, bestOut);
    }
    int chosen = bestInside >= 0 ? bestInside : bestOutside;
    if (chosen < 0) {
      hit.flags = kSurfaceDegenerate;
      return hit;
    }
    if (bestInside < 0) hit.flags |= kSurfaceFallback;
    hit.margin = std::min(hit.margin, margin(tuvs[chosen].y, tuvs[chosen].z));
    tri = children[chosen];
  }
  SurfaceRefHit fin = refractOnTriangleRef(s, s.height, ray, tri);
  fin.flags |= hit.flags & kSurfaceFallback;
  fin.margin = hit.margin;
  return fin;
}

SurfaceRefHit refractOnTriangleRef(const SurfaceRef& s, const HeightFunction& height, const GpuRay& ray, const SurfaceTriangle& tri) {
  SurfaceRefHit hit;
  hit.tri = tri;
  LoadedRay r = loadRayRef(ray);
  if (!r.valid) {
    hit.flags = kSurfaceInvalidRay;
    return hit;
  }
  dvec3 P[3];
  for (int c = 0; c < 3; c++) {
    int X, Y;
    finestCorner(s, tri, c, X, Y);
    P[c] = vertexAt(s, height, X, Y);
    hit.vertexNormals[c] = vertexNormalRef(s, height, X, Y);
  }
  dvec3 tuv;
  bool backFacing = false;
  bool ok = f64::surfaceHitForward(r.o, r.d, P[0], P[1], P[2], hit.vertexNormals[0], hit.vertexNormals[1], hit.vertexNormals[2],
                                   s.config.faceNormals, 1.0 / double(s.config.ior), tuv, hit.p, hit.n, hit.w, backFacing);
  if (!ok) {
    hit.flags = kSurfaceDegenerate;
    return hit;
  }
  hit.flags = kSurfaceHit | (backFacing ? kSurfaceBackFacing : 0u);
  hit.t = tuv.x;
  hit.u = tuv.y;
  hit.v = tuv.z;
  return hit;
}

std::map<std::pair<int, int>, double> surfaceBackwardRef(const SurfaceRef& s, const GpuRay& ray, const SurfaceTriangle& tri,
                                                         const glm::dvec3& gp, const glm::dvec3& gw) {
  std::map<std::pair<int, int>, double> g;
  LoadedRay r = loadRayRef(ray);
  if (!r.valid) return g;
  dvec3 P[3], N[3];
  int X[3], Y[3];
  for (int c = 0; c < 3; c++) {
    finestCorner(s, tri, c, X[c], Y[c]);
    P[c] = vertexAt(s, s.height, X[c], Y[c]);
    N[c] = vertexNormalRef(s, s.height, X[c], Y[c]);
  }
  dvec3 gP[3], gN[3];
  f64::surfaceHitBackward(r.o, r.d, P[0], P[1], P[2], N[0], N[1], N[2], s.config.faceNormals, 1.0 / double(s.config.ior), gp, gw, gP[0],
                          gP[1], gP[2], gN[0], gN[1], gN[2]);
  for (int c = 0; c < 3; c++) {
    g[{X[c], Y[c]}] += gP[c].z;
    for (int m = 0; m < 6; m++) {
      int di, dj;
      f64::ringOffset(m, di, dj);
      g[{X[c] + di, Y[c] + dj}] += f64::ringWeightX(m) * gN[c].x / s.hx + f64::ringWeightY(m) * gN[c].y / s.hy;
    }
  }
  return g;
}

}  // namespace refrax::ref
