#include "engine/surface_prior.h"

#include "engine/error.h"

namespace refrax {

double slopePrior(const std::vector<float>& heights, const GridLayout& g, double lambda, std::vector<float>* grad) {
  size_t last = g.first + size_t(g.cellsY) * g.rowLength + g.cellsX;
  if (g.cellsX == 0 || g.cellsY == 0 || g.rowLength < size_t(g.cellsX) + 1 || last >= heights.size())
    fail("slopePrior: the grid does not fit the height array");
  if (grad && grad->size() != heights.size()) fail("slopePrior: the gradient array is not sized like the heights");
  const double edges = double(g.cellsX) * (g.cellsY + 1) + double(g.cellsY) * (g.cellsX + 1);
  std::vector<double> dE(grad ? heights.size() : 0, 0.0);
  double energy = 0;
  auto edge = [&](size_t a, size_t b, double spacing) {
    double slope = (double(heights[a]) - double(heights[b])) / spacing;
    energy += slope * slope;
    if (grad) {
      double d = 2 * slope / spacing;
      dE[a] += d;
      dE[b] -= d;
    }
  };
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) {
      size_t k = g.first + size_t(j) * g.rowLength + i;
      if (i < g.cellsX) edge(k, k + 1, g.spacingX);
      if (j < g.cellsY) edge(k, k + g.rowLength, g.spacingY);
    }
  if (grad)
    for (size_t k = 0; k < dE.size(); k++) (*grad)[k] += float(lambda * dE[k] / edges);
  return lambda * energy / edges;
}

}  // namespace refrax
