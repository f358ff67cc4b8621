#include "engine/train/sweep_loss.h"

#include <algorithm>
#include <cmath>

namespace refrax {
namespace {

// T and its gradient in (x, y) at a point, bilinear between cell centres; false where one of
// the four cells has no depth (and so no agreed colour).
bool sampleTexture(const DepthMap& map, double x, double y, double T[3], double dTdx[3], double dTdy[3]) {
  const double fx = (x - map.xMin) / map.cellSize - 0.5, fy = (y - map.yMin) / map.cellSize - 0.5;
  const double ix = std::floor(fx), iy = std::floor(fy);
  if (!(ix >= 0 && iy >= 0 && ix + 1 < map.cellsX && iy + 1 < map.cellsY)) return false;
  const double a = fx - ix, b = fy - iy;
  const size_t c00 = size_t(iy) * map.cellsX + size_t(ix), c10 = c00 + 1, c01 = c00 + map.cellsX, c11 = c01 + 1;
  for (size_t c : {c00, c10, c01, c11})
    if (!std::isfinite(map.z[c])) return false;
  for (int ch = 0; ch < 3; ch++) {
    const double t00 = map.rgb[c00 * 3 + ch], t10 = map.rgb[c10 * 3 + ch], t01 = map.rgb[c01 * 3 + ch], t11 = map.rgb[c11 * 3 + ch];
    T[ch] = (1 - a) * (1 - b) * t00 + a * (1 - b) * t10 + (1 - a) * b * t01 + a * b * t11;
    dTdx[ch] = ((1 - b) * (t10 - t00) + b * (t11 - t01)) / map.cellSize;
    dTdy[ch] = ((1 - a) * (t01 - t00) + a * (t11 - t10)) / map.cellSize;
  }
  return true;
}

bool landAt(const GpuRay& r, double z, double& x, double& y) {
  if (!(r.dir[2] < 0) || !(r.origin[2] >= z)) return false;
  const double t = (z - r.origin[2]) / r.dir[2];
  x = r.origin[0] + t * r.dir[0];
  y = r.origin[1] + t * r.dir[1];
  return std::isfinite(x) && std::isfinite(y);
}

double medianDepth(const DepthMap& map) {
  std::vector<double> z;
  for (double v : map.z)
    if (std::isfinite(v)) z.push_back(v);
  if (z.empty()) return NAN;
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

// Where a ray lands: the plane of the cell it meets at depth z0, then of the cell it meets on
// that plane; false where it does not point down, starts under the plane, or finds no depth.
bool landOnMap(const DepthMap& map, double z0, const GpuRay& r, double& z, double& x, double& y) {
  z = z0;
  for (int pass = 0; pass < 2; pass++) {
    if (!std::isfinite(z) || !landAt(r, z, x, y)) return false;
    const long cell = map.cellAt(x, y);
    if (cell < 0 || !std::isfinite(map.z[size_t(cell)])) return false;
    z = map.z[size_t(cell)];
  }
  return landAt(r, z, x, y);
}

}  // namespace

double sweepTextureLoss(const SweepView& view, const DepthMap& map, double weight, std::vector<GpuRayGrad>& grads, size_t& used) {
  const Image& im = *view.image;
  grads.resize(view.rays.size(), GpuRayGrad{});
  const double z0 = medianDepth(map);
  double loss = 0;
  used = 0;
  for (size_t i = 0; i < view.rays.size(); i++) {
    const GpuRay& r = view.rays[i];
    double z, x, y;
    if (!landOnMap(map, z0, r, z, x, y)) continue;
    double T[3], dTdx[3], dTdy[3];
    if (!sampleTexture(map, x, y, T, dTdx, dTdy)) continue;
    double gx = 0, gy = 0;  // dLoss/dx, dLoss/dy of this ray
    for (int ch = 0; ch < 3; ch++) {
      const double e = double(im.pixels[i * size_t(im.channels) + ch]) - T[ch];
      loss += e * e;
      gx += -2 * e * dTdx[ch];
      gy += -2 * e * dTdy[ch];
    }
    used++;
    // x = o_xy + t d_xy with t = (z - o_z) / d_z, z held fixed
    const double dz = r.dir[2], t = (z - r.origin[2]) / dz, gd = (gx * r.dir[0] + gy * r.dir[1]) / dz;
    GpuRayGrad& g = grads[i];
    g.dOrigin[0] += float(weight * gx);
    g.dOrigin[1] += float(weight * gy);
    g.dOrigin[2] += float(weight * -gd);
    g.dDir[0] += float(weight * gx * t);
    g.dDir[1] += float(weight * gy * t);
    g.dDir[2] += float(weight * -t * gd);
  }
  return loss;
}

void addViewColours(const SweepView& view, const DepthMap& map, AgreedColours& colours) {
  const size_t cells = size_t(map.cellsX) * map.cellsY;
  if (colours.sums.size() != cells * 4) colours.sums.assign(cells * 4, 0.0), colours.viewSums.assign(cells * 4, 0.0);
  const double z0 = medianDepth(map);
  auto cellOf = [&](size_t i) {
    double z, x, y;
    return landOnMap(map, z0, view.rays[i], z, x, y) ? map.cellAt(x, y) : -1L;
  };
  forEachViewCellMean(view, cellOf, colours.viewSums, colours.touched, [&](uint32_t cell, const double m[3]) {
    double* a = &colours.sums[size_t(cell) * 4];
    for (int ch = 0; ch < 3; ch++) a[ch] += m[ch];
    a[3] += 1;
  });
}

void setAgreedColours(DepthMap& map, const AgreedColours& colours, uint32_t minViews) {
  const size_t cells = size_t(map.cellsX) * map.cellsY;
  if (colours.sums.size() != cells * 4) return;
  for (size_t c = 0; c < cells; c++) {
    const double* a = &colours.sums[c * 4];
    if (a[3] >= minViews)
      for (int ch = 0; ch < 3; ch++) map.rgb[c * 3 + ch] = float(a[ch] / a[3]);
  }
}

}  // namespace refrax
