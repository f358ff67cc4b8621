#pragma once
// Where the scene under the water lies, by a plane sweep (multi-view stereo through the water):
// each training view's pixels, followed along their rays as refracted by the current water
// surface, land on a stack of horizontal planes z = const; on the plane through a surface of
// the scene the views agree on its colour there. Per cell of an (x, y) grid the plane where
// the views' mean colours vary least (summed over a small window of cells, sub-plane refined
// by a parabola) is that cell's depth.
//
// Why: the Gaussians drawn uniformly in the box (3DGS's fallback without SfM points) keep
// their initial spread in depth: on the strong-wave tiny preset the opaque ones ended spread
// over 0.5 m around a scene 0.2 m deep, and the water's error followed the scene's relief
// (docs/experiments/2026-11-26-plane-sweep.md). --init-depth sweep draws them at the swept depth instead.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/io/image_io.h"
#include "engine/trace/rays.h"

namespace refrax {

// One view: a ray per pixel (row-major, the image's size; as they leave the water), its image.
struct SweepView {
  std::vector<GpuRay> rays;
  const Image* image = nullptr;
};

// One view's pixels binned into cells (cellOf(i): pixel i's cell, or -1), and each cell the view
// reached handed to add(cell, its mean colour r, g, b). viewSums (4 doubles per cell, zero
// between calls) and touched are the caller's scratch. Why only the cells reached: a pass over
// every (cell, view), zeroing and reading, took most of a sweep's time (256 x 192 pixels, 12
// views, 319^2 cells).
template <class CellOf, class Add>
void forEachViewCellMean(const SweepView& view, CellOf cellOf, std::vector<double>& viewSums, std::vector<uint32_t>& touched, Add add) {
  const Image& im = *view.image;
  for (size_t i = 0; i < view.rays.size(); i++) {
    const long cell = cellOf(i);
    if (cell < 0) continue;
    double* s = &viewSums[size_t(cell) * 4];
    if (s[3] == 0) touched.push_back(uint32_t(cell));
    for (int ch = 0; ch < 3; ch++) s[ch] += im.pixels[i * size_t(im.channels) + ch];
    s[3] += 1;
  }
  for (uint32_t cell : touched) {
    double* s = &viewSums[size_t(cell) * 4];
    const double mean[3] = {s[0] / s[3], s[1] / s[3], s[2] / s[3]};
    add(cell, mean);
    std::fill(s, s + 4, 0.0);
  }
  touched.clear();
}

struct PlaneSweepConfig {
  double xMin = 0, yMin = 0, xMax = 0, yMax = 0;  // the grid's area (the Gaussians' box)
  double zMin = 0, zMax = 0;                       // the planes' range
  uint32_t planes = 128;
  double cellSize = 0;        // <= 0: twice the pixel footprint at mid depth (sweepCellSize)
  uint32_t windowRadius = 2;  // costs summed over (2r + 1)^2 cells
  uint32_t minViews = 3;      // a (cell, plane) needs this many views landing in it
  // A cell's depth is kept when its best cost is below this fraction of its median cost
  // over the planes (a textureless cell's costs are flat: no depth).
  double confidence = 0.8;
};

struct DepthMap {
  uint32_t cellsX = 0, cellsY = 0;
  double xMin = 0, yMin = 0, cellSize = 0;
  std::vector<double> z;        // per cell, NaN where no depth was found
  std::vector<float> rgb;       // per cell, the views' mean colour at that depth
  // Per cell, the least windowed variance of the views' colours over the planes (how well the
  // views agree there at their best depth), kept with or without a confident depth; NaN where
  // too few planes saw the cell to compare them.
  std::vector<double> bestCost;
  // The cell holding (x, y), or -1 outside the grid.
  long cellAt(double x, double y) const;
};

// Twice the distance between where two neighbouring pixels' rays at the image centre meet
// the plane z, the largest over the views: about four rays per cell and view.
double sweepCellSize(const std::vector<SweepView>& views, double z);

DepthMap planeSweepDepth(const std::vector<SweepView>& views, PlaneSweepConfig config);

// How well the views agree through one water against another (the same views and sweep grid):
// the mean bestCost of each over the cells where both have one. Why: with no ground truth, a
// surface that explains the views worse than the flat start (the views' colours of the scene
// under it disagree more) is wrong, however low the training loss the Gaussians reach through it.
struct SweepAgreement {
  double cost = 0, reference = 0;  // mean bestCost of the water tested, of the reference water
  size_t cells = 0;                // cells compared
};
SweepAgreement compareSweepCosts(const DepthMap& tested, const DepthMap& reference);

}  // namespace refrax
