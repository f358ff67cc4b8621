#include "engine/surface/surface_prior.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/base/error.h"

namespace refrax {

namespace {

void checkGridFits(const std::vector<float>& heights, const GridLayout& g, const std::vector<float>* grad, const char* who) {
  size_t last = g.first + size_t(g.cellsY) * g.rowLength + g.cellsX;
  if (g.cellsX == 0 || g.cellsY == 0 || g.rowLength < size_t(g.cellsX) + 1 || last >= heights.size())
    fail(std::string(who) + ": the grid does not fit the height array");
  if (grad && grad->size() != heights.size()) fail(std::string(who) + ": the gradient array is not sized like the heights");
}

}  // namespace

double slopePrior(const std::vector<float>& heights, const GridLayout& g, double lambda, std::vector<float>* grad) {
  checkGridFits(heights, g, grad, "slopePrior");
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

double levelPrior(const std::vector<float>& heights, const GridLayout& g, const std::vector<double>& weights, double lambda,
                  std::vector<float>* grad, int degree, double warpShare) {
  if (degree < 1 || degree > kMaxLevelPriorDegree) fail("levelPrior: the degree is outside 1-" + std::to_string(kMaxLevelPriorDegree));
  checkGridFits(heights, g, grad, "levelPrior");
  if (weights.size() != heights.size()) fail("levelPrior: the weights are not sized like the heights");
  // The seen vertices, their weights and positions (in [-1, 1] over the grid's longer side: the
  // span of the basis does not depend on the origin or the scale, and a centred unit square keeps
  // the Gram matrix of a quartic well conditioned).
  const double side = std::max(g.cellsX * g.spacingX, g.cellsY * g.spacingY);
  std::vector<size_t> slot;
  std::vector<double> w, x, y;
  double total = 0;
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) {
      size_t k = g.first + size_t(j) * g.rowLength + i;
      if (!std::isfinite(weights[k]) || weights[k] < 0) fail("levelPrior: a weight is negative or not finite");
      if (weights[k] == 0) continue;
      slot.push_back(k);
      w.push_back(weights[k]);
      x.push_back((2.0 * i - g.cellsX) * g.spacingX / side);
      y.push_back((2.0 * j - g.cellsY) * g.spacingY / side);
      total += weights[k];
    }
  if (slot.empty()) return 0.0;
  const size_t n = slot.size();
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0;
    for (size_t k = 0; k < n; k++) sum += w[k] * a[k] * b[k];
    return sum / total;
  };
  // The monomials x^a y^b of total degree up to `degree`, the constant first, made orthonormal in
  // the weighted mean (modified Gram-Schmidt, two passes, which keep a quartic's basis orthogonal
  // to rounding); then E = lambda x the sum of the squared coefficients past the constant.
  std::vector<std::vector<double>> q;
  std::vector<double> share;  // each basis function's weight, as a share of lambda
  for (int total = 0; total <= degree; total++)
    for (int a = total; a >= 0; a--) {
      std::vector<double> b(n);
      for (size_t k = 0; k < n; k++) b[k] = std::pow(x[k], a) * std::pow(y[k], total - a);
      const double norm0 = std::sqrt(dot(b, b));
      for (int pass = 0; pass < 2; pass++)
        for (const auto& e : q) {
          double c = dot(e, b);
          for (size_t k = 0; k < n; k++) b[k] -= c * e[k];
        }
      const double norm = std::sqrt(dot(b, b));
      if (norm <= 1e-9 * norm0) continue;  // in the span of the others at these vertices (or none)
      for (double& v : b) v /= norm;
      q.push_back(std::move(b));
      share.push_back(total > 2 ? warpShare : 1.0);
    }
  std::vector<double> h(n);
  for (size_t k = 0; k < n; k++) h[k] = heights[slot[k]];
  double energy = 0;
  std::vector<double> dE(n, 0.0);
  for (size_t m = 1; m < q.size(); m++) {  // q[0] is the constant
    const double c = dot(q[m], h);
    energy += share[m] * c * c;
    for (size_t k = 0; k < n; k++) dE[k] += 2 * share[m] * c * w[k] * q[m][k] / total;
  }
  if (grad)
    for (size_t k = 0; k < n; k++) (*grad)[slot[k]] += float(lambda * dE[k]);
  return lambda * energy;
}

}  // namespace refrax
