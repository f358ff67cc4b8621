#include "engine/train/plane_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/base/error.h"

namespace refrax {
namespace {

// Where the ray meets the plane z, or false (pointing up, or starting under the plane).
bool rayAtPlane(const GpuRay& r, double z, double& x, double& y) {
  if (!(r.dir[2] < 0) || !(r.origin[2] >= z)) return false;
  double t = (z - r.origin[2]) / r.dir[2];
  x = r.origin[0] + t * r.dir[0];
  y = r.origin[1] + t * r.dir[1];
  return std::isfinite(x) && std::isfinite(y);
}

}  // namespace

long DepthMap::cellAt(double x, double y) const {
  double fx = (x - xMin) / cellSize, fy = (y - yMin) / cellSize;
  if (!(fx >= 0 && fy >= 0 && fx < cellsX && fy < cellsY)) return -1;
  return long(fy) * long(cellsX) + long(fx);
}

double sweepCellSize(const std::vector<SweepView>& views, double z) {
  double size = 0;
  for (const SweepView& v : views) {
    int w = v.image->width, h = v.image->height;
    if (w < 2) continue;
    size_t centre = size_t(h / 2) * size_t(w) + size_t(w / 2 - 1);
    double ax, ay, bx, by;
    if (rayAtPlane(v.rays[centre], z, ax, ay) && rayAtPlane(v.rays[centre + 1], z, bx, by))
      size = std::max(size, 2.0 * std::hypot(bx - ax, by - ay));
  }
  return size;
}

DepthMap planeSweepDepth(const std::vector<SweepView>& views, PlaneSweepConfig c) {
  if (!(c.xMax > c.xMin && c.yMax > c.yMin && c.zMax > c.zMin)) fail("plane sweep: empty area or depth range");
  if (c.planes < 3) fail("plane sweep: needs at least 3 planes");
  for (const SweepView& v : views)
    if (!v.image || v.image->channels < 3 || v.rays.size() != size_t(v.image->width) * size_t(v.image->height))
      fail("plane sweep: a view's rays do not match its image");
  if (!(c.cellSize > 0)) c.cellSize = sweepCellSize(views, 0.5 * (c.zMin + c.zMax));
  if (!(c.cellSize > 0)) c.cellSize = (c.xMax - c.xMin) / 64;  // no view sees the box's middle
  DepthMap map;
  map.xMin = c.xMin;
  map.yMin = c.yMin;
  map.cellSize = c.cellSize;
  map.cellsX = uint32_t(std::max(1.0, std::ceil((c.xMax - c.xMin) / c.cellSize)));
  map.cellsY = uint32_t(std::max(1.0, std::ceil((c.yMax - c.yMin) / c.cellSize)));
  const size_t cells = size_t(map.cellsX) * map.cellsY, V = views.size(), P = c.planes;
  const double spacing = (c.zMax - c.zMin) / double(P);
  const double inf = std::numeric_limits<double>::infinity();

  std::vector<double> cost(cells * P, inf);   // windowed variance of the views' mean colours
  std::vector<float> colour(cells * P * 3, 0.0f);
  std::vector<double> sums(cells * V * 4);    // per (cell, view): r, g, b, count
  std::vector<double> spread(cells), viewsIn(cells);  // per cell: sum of squares, degrees of freedom
  const long R = long(c.windowRadius);
  for (size_t k = 0; k < P; k++) {
    const double z = c.zMin + (double(k) + 0.5) * spacing;
    std::fill(sums.begin(), sums.end(), 0.0);
    for (size_t v = 0; v < V; v++) {
      const Image& im = *views[v].image;
      for (size_t i = 0; i < views[v].rays.size(); i++) {
        double x, y;
        if (!rayAtPlane(views[v].rays[i], z, x, y)) continue;
        long cell = map.cellAt(x, y);
        if (cell < 0) continue;
        double* s = &sums[(size_t(cell) * V + v) * 4];
        for (int ch = 0; ch < 3; ch++) s[ch] += im.pixels[i * size_t(im.channels) + ch];
        s[3] += 1;
      }
    }
    // Per cell: the spread of the views' mean colours about their mean, and its colour.
    for (size_t cell = 0; cell < cells; cell++) {
      double mean[3] = {0, 0, 0}, n = 0, sq = 0;
      for (size_t v = 0; v < V; v++) {
        const double* s = &sums[(cell * V + v) * 4];
        if (s[3] == 0) continue;
        for (int ch = 0; ch < 3; ch++) {
          double m = s[ch] / s[3];
          mean[ch] += m;
          sq += m * m;
        }
        n += 1;
      }
      spread[cell] = 0;
      viewsIn[cell] = 0;
      if (n == 0) continue;
      for (int ch = 0; ch < 3; ch++) {
        mean[ch] /= n;
        colour[(cell * P + k) * 3 + ch] = float(mean[ch]);
      }
      if (n < c.minViews) continue;
      // Divided by n - 1 in the window below: the unbiased variance. Divided by n, cells
      // fewer views see (nearer the cameras, at the footprints' edges) would look better.
      spread[cell] = std::max(0.0, sq - n * (mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]));
      viewsIn[cell] = n - 1;
    }
    for (long cy = 0; cy < long(map.cellsY); cy++)
      for (long cx = 0; cx < long(map.cellsX); cx++) {
        double s = 0, n = 0;
        for (long wy = std::max(0L, cy - R); wy <= std::min(long(map.cellsY) - 1, cy + R); wy++)
          for (long wx = std::max(0L, cx - R); wx <= std::min(long(map.cellsX) - 1, cx + R); wx++) {
            size_t w = size_t(wy) * map.cellsX + size_t(wx);
            s += spread[w];
            n += viewsIn[w];
          }
        if (n > 0) cost[(size_t(cy) * map.cellsX + size_t(cx)) * P + k] = s / n;
      }
  }

  map.z.assign(cells, std::numeric_limits<double>::quiet_NaN());
  map.rgb.assign(cells * 3, 0.0f);
  map.bestCost.assign(cells, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> finite;
  for (size_t cell = 0; cell < cells; cell++) {
    const double* cc = &cost[cell * P];
    finite.clear();
    for (size_t k = 0; k < P; k++)
      if (cc[k] < inf) finite.push_back(cc[k]);
    if (finite.size() < P / 2) continue;  // seen on too few of the planes to compare them
    size_t best = size_t(std::min_element(cc, cc + P) - cc);
    map.bestCost[cell] = cc[best];
    std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
    double median = finite[finite.size() / 2];
    if (!(cc[best] < c.confidence * median)) continue;
    double offset = 0;
    if (best > 0 && best + 1 < P && cc[best - 1] < inf && cc[best + 1] < inf) {
      double curvature = cc[best - 1] - 2 * cc[best] + cc[best + 1];
      if (curvature > 0) offset = std::clamp(0.5 * (cc[best - 1] - cc[best + 1]) / curvature, -0.5, 0.5);
    }
    map.z[cell] = c.zMin + (double(best) + 0.5 + offset) * spacing;
    for (int ch = 0; ch < 3; ch++) map.rgb[cell * 3 + ch] = colour[(cell * P + best) * 3 + ch];
  }
  return map;
}

SweepAgreement compareSweepCosts(const DepthMap& tested, const DepthMap& reference) {
  if (tested.bestCost.size() != reference.bestCost.size() || tested.cellsX != reference.cellsX || tested.cellSize != reference.cellSize)
    fail("plane sweep: the two sweeps' grids differ");
  SweepAgreement a;
  for (size_t k = 0; k < tested.bestCost.size(); k++)
    if (std::isfinite(tested.bestCost[k]) && std::isfinite(reference.bestCost[k])) {
      a.cost += tested.bestCost[k];
      a.reference += reference.bestCost[k];
      a.cells++;
    }
  if (a.cells > 0) {
    a.cost /= double(a.cells);
    a.reference /= double(a.cells);
  }
  return a;
}

}  // namespace refrax
