// The slope prior of --surface-smoothness (engine/surface_prior.h): its value on a tilted
// plane, its gradient against central differences on random heights (a bordered grid as the
// water surface stores it, and a plain one), and its refusals.
#include <cmath>
#include <random>
#include <vector>

#include <doctest/doctest.h>

#include "engine/error.h"
#include "engine/surface_prior.h"

using namespace refrax;

namespace {

GridLayout bordered(uint32_t cx, uint32_t cy, double sx, double sy) {
  GridLayout g{cx, cy, size_t(cx) + 3, size_t(cx) + 4, sx, sy};
  return g;
}

size_t slots(const GridLayout& g) { return (size_t(g.cellsY) + 3) * g.rowLength; }  // with the border ring

}  // namespace

TEST_CASE("slope prior: lambda times the mean squared edge slope, a tilted plane has the tilt's squared slope on its x edges") {
  GridLayout g{6, 4, 7, 0, 0.25, 0.5};
  std::vector<float> h(7 * 5);
  for (uint32_t j = 0; j <= 4; j++)
    for (uint32_t i = 0; i <= 6; i++) h[j * 7 + i] = float(0.125 * i);  // slope 0.125 / 0.25 = 0.5 along x, 0 along y
  const double xEdges = 6.0 * 5, edges = xEdges + 4.0 * 7;
  CHECK(slopePrior(h, g, 3.0, nullptr) == doctest::Approx(3.0 * 0.25 * xEdges / edges).epsilon(1e-12));
  std::vector<float> flat(h.size(), 0.7f);
  CHECK(slopePrior(flat, g, 3.0, nullptr) == 0.0);
}

TEST_CASE("slope prior: the gradient matches central differences on random heights, and only grid slots get one") {
  std::mt19937 rng(20261124u);
  std::normal_distribution<float> N(0.0f, 0.05f);
  for (GridLayout g : {bordered(9, 7, 0.1, 0.15), GridLayout{5, 8, 6, 0, 0.3, 0.2}}) {
    size_t n = g.first ? slots(g) : size_t(g.rowLength) * (g.cellsY + 1);
    std::vector<float> h(n);
    for (float& x : h) x = N(rng);
    const double lambda = 0.37;
    std::vector<float> grad(n, 0.0f);
    grad[0] = 5.0f;  // added to, not overwritten
    const double e = slopePrior(h, g, lambda, &grad);
    CHECK(e > 0);
    double worst = 0, largest = 0;
    size_t touched = 0;
    for (size_t k = 0; k < n; k++) {
      // E is quadratic in the heights: central differences are exact up to rounding.
      const float step = 1.0f / 64.0f;
      std::vector<float> up(h), down(h);
      up[k] += step;
      down[k] -= step;
      double fd = (slopePrior(up, g, lambda, nullptr) - slopePrior(down, g, lambda, nullptr)) / double(up[k] - down[k]);
      double got = grad[k] - (k == 0 ? 5.0 : 0.0);
      worst = std::max(worst, std::abs(got - fd));
      largest = std::max(largest, std::abs(fd));
      size_t r = k >= g.first ? (k - g.first) / g.rowLength : size_t(-1), i = k >= g.first ? (k - g.first) % g.rowLength : size_t(-1);
      bool inGrid = k >= g.first && r <= g.cellsY && i <= g.cellsX;
      if (!inGrid) CHECK(got == 0.0);
      touched += inGrid && fd != 0;
    }
    INFO("worst " << worst << " of " << largest);
    CHECK(largest > 0);
    CHECK(worst < 1e-5 * largest);
    CHECK(touched == (size_t(g.cellsX) + 1) * (g.cellsY + 1));
  }
}

TEST_CASE("slope prior: a grid that does not fit the heights, or a gradient of another size, is refused") {
  std::vector<float> h(20, 0.0f), wrong(19, 0.0f);
  CHECK_THROWS_AS(slopePrior(h, GridLayout{4, 4, 5, 0, 1, 1}, 1.0, nullptr), Error);  // 25 vertices
  CHECK_THROWS_AS(slopePrior(h, GridLayout{4, 3, 4, 0, 1, 1}, 1.0, nullptr), Error);  // row shorter than a grid row
  CHECK_THROWS_AS(slopePrior(h, GridLayout{0, 3, 5, 0, 1, 1}, 1.0, nullptr), Error);
  CHECK_THROWS_AS(slopePrior(h, GridLayout{4, 3, 5, 0, 1, 1}, 1.0, &wrong), Error);
  CHECK_NOTHROW(slopePrior(h, GridLayout{4, 3, 5, 0, 1, 1}, 1.0, nullptr));
}
