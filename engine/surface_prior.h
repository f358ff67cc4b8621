#pragma once
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

}  // namespace refrax
