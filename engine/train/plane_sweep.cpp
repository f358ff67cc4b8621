#include "engine/train/plane_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

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

namespace {

// One plane's scratch, one per thread: the planes are swept independently.
struct PlaneScratch {
  std::vector<double> viewSums;   // per cell: r, g, b, count of the view being added (zero between views)
  std::vector<uint32_t> touched;  // the cells that view's rays landed in
  std::vector<double> views;      // per cell: the views' mean r, g, b summed, their squares summed, the views
  std::vector<double> spread, dof, rowSpread, rowDof;  // per cell; the window's sums along x
  explicit PlaneScratch(size_t cells)
      : viewSums(cells * 4, 0.0), views(cells * 5), spread(cells), dof(cells), rowSpread(cells), rowDof(cells) {
    touched.reserve(cells);  // allocated here, so that a sweeping thread never allocates (nor throws)
  }
};

// out = in summed over 2R + 1 cells along one axis of an X x Y grid (step 1: along x; step X:
// along y), the window cut at the grid's edges.
void windowSums(const std::vector<double>& in, std::vector<double>& out, long X, long Y, long R, long step) {
  const long length = step == 1 ? X : Y;
  for (long cy = 0; cy < Y; cy++)
    for (long cx = 0; cx < X; cx++) {
      const long at = step == 1 ? cx : cy, cell = cy * X + cx;
      double sum = 0;
      for (long d = std::max(-R, -at); d <= std::min(R, length - 1 - at); d++) sum += in[size_t(cell + d * step)];
      out[size_t(cell)] = sum;
    }
}

// Plane k at height z: per cell, the views' mean colour there and the spread of the views'
// mean colours about it; then the spread summed over a window of cells and divided by its
// degrees of freedom, into cost[cell * planes + k].
void sweepPlane(const std::vector<SweepView>& views, const DepthMap& map, const PlaneSweepConfig& c, size_t k, double z,
                PlaneScratch& w, std::vector<double>& cost, std::vector<float>& colour) {
  const size_t cells = size_t(map.cellsX) * map.cellsY, P = c.planes;
  std::fill(w.views.begin(), w.views.end(), 0.0);
  for (const SweepView& v : views) {
    auto cellOf = [&](size_t i) {
      double x, y;
      return rayAtPlane(v.rays[i], z, x, y) ? map.cellAt(x, y) : -1L;
    };
    forEachViewCellMean(v, cellOf, w.viewSums, w.touched, [&](uint32_t cell, const double m[3]) {
      double* a = &w.views[size_t(cell) * 5];
      for (int ch = 0; ch < 3; ch++) a[ch] += m[ch], a[3] += m[ch] * m[ch];
      a[4] += 1;
    });
  }
  for (size_t cell = 0; cell < cells; cell++) {
    const double* a = &w.views[cell * 5];
    const double n = a[4];
    w.spread[cell] = 0;
    w.dof[cell] = 0;
    if (n == 0) continue;
    double mean[3];
    for (int ch = 0; ch < 3; ch++) {
      mean[ch] = a[ch] / n;
      colour[(cell * P + k) * 3 + ch] = float(mean[ch]);
    }
    if (n < c.minViews) continue;
    // Divided by n - 1 in the window below: the unbiased variance. Divided by n, cells
    // fewer views see (nearer the cameras, at the footprints' edges) would look better.
    w.spread[cell] = std::max(0.0, a[3] - n * (mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]));
    w.dof[cell] = n - 1;
  }
  // The window's sums, along x and then along y (back into spread and dof).
  const long R = long(c.windowRadius), X = long(map.cellsX), Y = long(map.cellsY);
  windowSums(w.spread, w.rowSpread, X, Y, R, 1);
  windowSums(w.dof, w.rowDof, X, Y, R, 1);
  windowSums(w.rowSpread, w.spread, X, Y, R, X);
  windowSums(w.rowDof, w.dof, X, Y, R, X);
  for (size_t cell = 0; cell < cells; cell++)
    if (w.dof[cell] > 0) cost[cell * P + k] = w.spread[cell] / w.dof[cell];
}

}  // namespace

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
  const size_t cells = size_t(map.cellsX) * map.cellsY, P = c.planes;
  const double spacing = (c.zMax - c.zMin) / double(P);
  const double inf = std::numeric_limits<double>::infinity();

  std::vector<double> cost(cells * P, inf);  // windowed variance of the views' mean colours
  std::vector<float> colour(cells * P * 3, 0.0f);
  // The planes on threads, each a contiguous run of them (so that two threads seldom write
  // neighbouring costs). A plane's result does not depend on the thread count. At most 8
  // threads: each one's scratch is 13 doubles per cell.
  const size_t threads = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, std::min<size_t>(8, P));
  std::vector<PlaneScratch> scratch(threads, PlaneScratch(cells));
  auto sweepPlanes = [&](size_t t) {
    for (size_t k = t * P / threads; k < (t + 1) * P / threads; k++)
      sweepPlane(views, map, c, k, c.zMin + (double(k) + 0.5) * spacing, scratch[t], cost, colour);
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; t++) pool.emplace_back(sweepPlanes, t);
  sweepPlanes(0);
  for (std::thread& t : pool) t.join();

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
