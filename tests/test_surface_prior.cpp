// The slope prior of --surface-smoothness (engine/surface/surface_prior.h): its value on a tilted
// plane, its gradient against central differences on random heights (a bordered grid as the
// water surface stores it, and a plain one), and its refusals; the level prior of --level-prior
// likewise, on exact quadratics, random heights and weights, and degenerate seen regions.
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "engine/base/error.h"
#include "engine/surface/surface_prior.h"

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

namespace {

// Random weights on a bordered grid: 0 on the border ring, on about a quarter of the grid's
// vertices and on a 3-vertex-wide strip (unseen water), else 1-8 views.
std::vector<double> randomWeights(const GridLayout& g, size_t n, std::mt19937& rng) {
  std::vector<double> w(n, 0.0);
  std::uniform_int_distribution<int> views(0, 8);
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 2; i <= g.cellsX; i++) {  // columns 0-1 and the ring unseen
      int v = views(rng);
      w[g.first + j * g.rowLength + i] = v <= 2 ? 0.0 : double(v);
    }
  return w;
}

// Heights f(i, j) at the grid's vertices (i, j), 0 off the grid.
template <class F>
std::vector<float> onGrid(const GridLayout& g, size_t n, F f) {
  std::vector<float> h(n, 0.0f);
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) h[g.first + j * g.rowLength + i] = float(f(i, j));
  return h;
}

double weightedVariance(const std::vector<float>& h, const std::vector<double>& w) {
  double sw = 0, m = 0, v = 0;
  for (size_t k = 0; k < h.size(); k++) sw += w[k], m += w[k] * h[k];
  m /= sw;
  for (size_t k = 0; k < h.size(); k++) v += w[k] * (h[k] - m) * (h[k] - m);
  return v / sw;
}

}  // namespace

TEST_CASE("level prior: a quadratic surface is all tilt and bowl (E = lambda x its weighted variance), a constant is none") {
  std::mt19937 rng(20261125u);
  for (GridLayout g : {bordered(9, 7, 0.1, 0.15), bordered(12, 5, 0.2, 0.05)}) {
    const size_t n = slots(g);
    std::vector<double> w = randomWeights(g, n, rng);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const double c[6] = {U(rng), U(rng), U(rng), U(rng), U(rng), U(rng)};
    // any origin: the span does not move
    auto at = [&](uint32_t i, uint32_t j) { return std::pair<double, double>{i * g.spacingX - 0.4, j * g.spacingY + 0.3}; };
    std::vector<float> h = onGrid(g, n, [&](uint32_t i, uint32_t j) {
      auto [x, y] = at(i, j);
      return c[0] + c[1] * x + c[2] * y + c[3] * x * x + c[4] * x * y + c[5] * y * y;
    });
    const double lambda = 2.5;
    INFO("cells " << g.cellsX << " x " << g.cellsY);
    CHECK(levelPrior(h, g, w, lambda, nullptr) == doctest::Approx(lambda * weightedVariance(h, w)).epsilon(1e-6));
    std::vector<float> flat(n, 0.37f);
    CHECK(levelPrior(flat, g, w, lambda, nullptr) == doctest::Approx(0.0).scale(1e-12));
    // The sine across the seen region has some tilt and bowl, but far less than its variance.
    std::vector<float> wave = onGrid(g, n, [](uint32_t i, uint32_t j) { return std::sin(7.0 * i + 5.0 * j); });
    const double e = levelPrior(wave, g, w, 1.0, nullptr);
    CHECK(e > 0);
    CHECK(e < 0.2 * weightedVariance(wave, w));
    // The tilt alone: a plane is all tilt, a bowl only its part along {x, y}.
    std::vector<float> plane = onGrid(g, n, [&](uint32_t i, uint32_t j) {
      auto [x, y] = at(i, j);
      return c[0] + c[1] * x + c[2] * y;
    });
    std::vector<float> bowl = onGrid(g, n, [&](uint32_t i, uint32_t j) {
      auto [x, y] = at(i, j);
      return c[3] * x * x + c[4] * x * y + c[5] * y * y;
    });
    CHECK(levelPrior(plane, g, w, lambda, nullptr, 1) == doctest::Approx(lambda * weightedVariance(plane, w)).epsilon(1e-6));
    CHECK(levelPrior(bowl, g, w, lambda, nullptr, 1) < levelPrior(bowl, g, w, lambda, nullptr, 2) - 1e-9);
  }
}

TEST_CASE("level prior of degree 4: a quartic is all of it, a bowl the same as at degree 2, a fine sine little, and degrees outside 1-6 are refused") {
  std::mt19937 rng(20261207u);
  for (GridLayout g : {bordered(16, 12, 0.1, 0.15), bordered(24, 9, 0.2, 0.05)}) {
    const size_t n = slots(g);
    std::vector<double> w = randomWeights(g, n, rng);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    std::vector<double> c(15);
    for (double& v : c) v = U(rng);
    auto at = [&](uint32_t i, uint32_t j) { return std::pair<double, double>{i * g.spacingX - 0.9, j * g.spacingY + 0.2}; };
    std::vector<float> quartic = onGrid(g, n, [&](uint32_t i, uint32_t j) {
      auto [x, y] = at(i, j);
      double h = 0;
      int m = 0;
      for (int total = 0; total <= 4; total++)
        for (int a = total; a >= 0; a--) h += c[m++] * std::pow(x, a) * std::pow(y, total - a);
      return h;
    });
    std::vector<float> bowl = onGrid(g, n, [&](uint32_t i, uint32_t j) {
      auto [x, y] = at(i, j);
      return c[3] * x * x + c[4] * x * y + c[5] * y * y + c[1] * x;
    });
    std::vector<float> wave = onGrid(g, n, [](uint32_t i, uint32_t j) { return std::sin(7.0 * i + 5.0 * j); });
    INFO("cells " << g.cellsX << " x " << g.cellsY);
    const double lambda = 1.5;
    CHECK(levelPrior(quartic, g, w, lambda, nullptr, 4) == doctest::Approx(lambda * weightedVariance(quartic, w)).epsilon(1e-5));
    CHECK(levelPrior(quartic, g, w, lambda, nullptr, 3) < levelPrior(quartic, g, w, lambda, nullptr, 4) - 1e-9);
    CHECK(levelPrior(bowl, g, w, lambda, nullptr, 4) == doctest::Approx(levelPrior(bowl, g, w, lambda, nullptr, 2)).epsilon(1e-6));
    CHECK(levelPrior(wave, g, w, 1.0, nullptr, 4) < 0.2 * weightedVariance(wave, w));
    // The warp's share: 0 leaves the bowl's prior, a share in between weighs what lies past it.
    CHECK(levelPrior(quartic, g, w, lambda, nullptr, 4, 0.0) == doctest::Approx(levelPrior(quartic, g, w, lambda, nullptr, 2)).epsilon(1e-6));
    const double past = levelPrior(quartic, g, w, lambda, nullptr, 4) - levelPrior(quartic, g, w, lambda, nullptr, 2);
    CHECK(past > 0);
    CHECK(levelPrior(quartic, g, w, lambda, nullptr, 4, 0.25) ==
          doctest::Approx(levelPrior(quartic, g, w, lambda, nullptr, 2) + 0.25 * past).epsilon(1e-6));
    CHECK_THROWS_AS(levelPrior(wave, g, w, 1.0, nullptr, 0), Error);
    CHECK_THROWS_AS(levelPrior(wave, g, w, 1.0, nullptr, kMaxLevelPriorDegree + 1), Error);
  }
}

TEST_CASE("level prior: the gradient matches central differences on random heights and weights at degrees 2 and 4, and unseen slots get none") {
  std::mt19937 rng(4242u);
  std::normal_distribution<float> N(0.0f, 0.05f);
  for (int trial = 0; trial < 3; trial++) {
    GridLayout g = trial == 2 ? GridLayout{7, 6, 8, 0, 0.3, 0.2} : bordered(9 + trial, 7, 0.1, 0.15);
    const size_t n = g.first ? slots(g) : g.rowLength * (g.cellsY + 1);
    std::vector<double> w = randomWeights(g, n, rng);
    std::vector<float> h(n);
    for (float& v : h) v = N(rng);
    const double lambda = 3.7;
    std::vector<float> grad(n, 0.0f);
    grad[1] = -2.0f;  // added to, not overwritten
    const int degree = trial == 0 ? 2 : 4;  // the bowl and the quartic, its warps weighted less
    const double share = trial == 2 ? 0.3 : 1.0;
    CHECK(levelPrior(h, g, w, lambda, &grad, degree, share) > 0);
    double worst = 0, largest = 0;
    for (size_t k = 0; k < n; k++) {
      const float step = 1.0f / 64.0f;  // E is quadratic in the heights: central differences are exact up to rounding
      std::vector<float> up(h), down(h);
      up[k] += step;
      down[k] -= step;
      double fd = (levelPrior(up, g, w, lambda, nullptr, degree, share) - levelPrior(down, g, w, lambda, nullptr, degree, share)) /
                  double(up[k] - down[k]);
      double got = grad[k] - (k == 1 ? -2.0 : 0.0);
      worst = std::max(worst, std::abs(got - fd));
      largest = std::max(largest, std::abs(fd));
      if (w[k] == 0) CHECK(got == 0.0);
    }
    INFO("trial " << trial << " (degree " << degree << "): worst " << worst << " of " << largest);
    CHECK(largest > 0);
    CHECK(worst < 1e-5 * largest);
  }
}

TEST_CASE("level prior: a seen region on one row keeps only its x terms, none seen is 0, bad weights are refused") {
  GridLayout g = bordered(8, 6, 0.1, 0.1);
  const size_t n = slots(g);
  std::vector<double> w(n, 0.0);
  for (uint32_t i = 0; i <= g.cellsX; i++) w[g.first + 3 * g.rowLength + i] = 1.0;  // row 3 only
  std::vector<float> h(n, 0.0f);
  for (uint32_t j = 0; j <= g.cellsY; j++)
    for (uint32_t i = 0; i <= g.cellsX; i++) h[g.first + j * g.rowLength + i] = float(0.02 * i + 0.5 * j);  // y tilt unseen
  std::vector<float> grad(n, 0.0f);
  const double e = levelPrior(h, g, w, 1.0, &grad);
  CHECK(std::isfinite(e));
  CHECK(e == doctest::Approx(weightedVariance(h, w)).epsilon(1e-6));  // the x tilt along the row
  for (size_t k = 0; k < n; k++) CHECK(std::isfinite(grad[k]));
  CHECK(levelPrior(h, g, std::vector<double>(n, 0.0), 1.0, nullptr) == 0.0);
  CHECK_THROWS_AS(levelPrior(h, g, std::vector<double>(n - 1, 1.0), 1.0, nullptr), Error);
  std::vector<double> bad(w);
  bad[g.first + 2] = -1.0;
  CHECK_THROWS_AS(levelPrior(h, g, bad, 1.0, nullptr), Error);
  bad[g.first + 2] = std::nan("");
  CHECK_THROWS_AS(levelPrior(h, g, bad, 1.0, nullptr), Error);
  CHECK_THROWS_AS(levelPrior(h, GridLayout{8, 6, 5, 0, 1, 1}, w, 1.0, nullptr), Error);
}
