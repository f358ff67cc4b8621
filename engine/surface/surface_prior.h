#pragma once
// Priors on the learned water, added to the image loss's gradient at the coarse grid's
// vertices before the height field's backward.
//
// --surface-smoothness: a weak prior on the learned water's slope,
//   E = lambda x mean over the coarse grid's edges of ((h_a - h_b) / spacing)^2,
// whose gradient joins the image loss's at the grid vertices before the height field's
// backward. Why: with a fast surface (the short-run settings) on scenes whose waves barely
// distort the images, the surface roughened until the image loss's gradient no longer
// predicted its own change and then ran away to metres (bench/presets.sh); a prior worth 1-2%
// of the image gradient near flat grows with the roughness and holds it.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace refrax {

// Where the grid's (cellsX + 1) x (cellsY + 1) vertices lie in a height array: vertex (i, j)
// at first + j * rowLength + i (a WaterSurface's coarse grid has a border ring: rowLength
// cellsX + 3, first rowLength + 1; a plain grid: rowLength cellsX + 1, first 0).
struct GridLayout {
  uint32_t cellsX = 0, cellsY = 0;
  size_t rowLength = 0, first = 0;
  double spacingX = 1, spacingY = 1;
};

// Returns E for the heights and, when grad is not null, adds dE/dheight to grad (same layout,
// sized like heights). Slots outside the grid are neither read nor written.
double slopePrior(const std::vector<float>& heights, const GridLayout& grid, double lambda, std::vector<float>* grad);

// --level-prior: E = lambda x the weighted mean square of the seen water's tilt and bowl:
// fit the heights by {1, x, y, x^2, xy, y^2} (to --level-prior-degree: every x^a y^b of
// a + b <= degree) in weighted least squares over the grid vertices
// of weight > 0 (weights sized like heights; the trainer weighs a vertex by the training views
// that see it); E is the fit less its constant, squared, weighted-averaged. Why: with
// near-vertical views a tilt or a bowl of the water acts as a prism or a lens whose shift and
// magnification the Gaussians absorb, so the images barely hold them, and on the strong-wave
// scene a 1-1.6 cm bowl grew in every run, even started at the true surface (issue 6).
// --anchor-mean-height holds the constant; this holds the next two orders. Returns E and, when
// grad is not null, adds dE/dheight to it (0 where the weight is 0 and outside the grid).
// Directions the weights cannot tell apart (a seen region on one line has no y) are left out.
// degree 1: the tilt alone ({1, x, y}), which leaves a long wave's curvature to the views;
// 3 and 4: the smooth warps past the bowl too, which the Gaussians absorb as well (on desk the
// learned water's excess error lay in its cubic and quartic parts; 2026-12-07-level-degree.md).
// warpShare: the terms past the bowl (degree 3 and up) weighted warpShare x lambda, so that a
// long true wave, which is partly such a warp, is held less than a tilt or a bowl.
constexpr int kMaxLevelPriorDegree = 6;
double levelPrior(const std::vector<float>& heights, const GridLayout& grid, const std::vector<double>& weights, double lambda,
                  std::vector<float>* grad, int degree = 2, double warpShare = 1.0);

}  // namespace refrax
