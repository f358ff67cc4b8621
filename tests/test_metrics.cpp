// Evaluation metrics: PSNR and SSIM on known cases, the surface distance against analytic
// planes and a brute-force search over a curved surface.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/base/error.h"
#include "engine/loss/metrics.h"
#include "engine/reference/image_loss_ref.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

Image constantImage(int w, int h, int c, float value) {
  Image im;
  im.width = w;
  im.height = h;
  im.channels = c;
  im.pixels.assign(size_t(w) * h * c, value);
  return im;
}

HeightGrid gridOf(int nx, int ny, double x0, double y0, double x1, double y1, double (*f)(double, double)) {
  HeightGrid g{nx, ny, x0, y0, x1, y1, {}};
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) g.heights.push_back(f(x0 + i * (x1 - x0) / (nx - 1), y0 + j * (y1 - y0) / (ny - 1)));
  return g;
}

}  // namespace

TEST_CASE("PSNR and SSIM metrics on known images, clear errors on mismatched shapes") {
  Image a = constantImage(20, 10, 3, 0.5f), b = constantImage(20, 10, 3, 0.6f);
  CHECK(psnr(a, b) == doctest::Approx(20.0).epsilon(1e-6));
  CHECK(std::isinf(psnr(a, a)));
  CHECK(ssim(a, a) == doctest::Approx(1.0).epsilon(1e-12));
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (auto& v : b.pixels) v = U(rng);
  CHECK(ssim(a, b) == doctest::Approx(ref::ssim(std::vector<double>(a.pixels.begin(), a.pixels.end()),
                                                std::vector<double>(b.pixels.begin(), b.pixels.end()), 20, 10, 3)));
  CHECK(ssim(a, b) < 0.5);
  CHECK_THROWS_AS(psnr(a, constantImage(20, 10, 4, 0.5f)), Error);
  CHECK_THROWS_AS(ssim(a, constantImage(10, 20, 3, 0.5f)), Error);
}

TEST_CASE("surface distance: exact on a tilted plane, vertical distance only bounds it") {
  // bilinear interpolation reproduces a plane exactly
  HeightGrid g = gridOf(9, 7, -2, -1.5, 2, 1.5, [](double x, double y) { return 0.3 * x - 0.2 * y + 0.1; });
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  glm::dvec3 n = glm::normalize(glm::dvec3(-0.3, 0.2, 1.0));
  double sumSq = 0;
  std::vector<glm::dvec3> points;
  for (int k = 0; k < 200; k++) {
    glm::dvec3 foot(U(rng), U(rng) * 0.8, 0);
    foot.z = 0.3 * foot.x - 0.2 * foot.y + 0.1;
    double d = 0.4 * U(rng);
    glm::dvec3 p = foot + d * n;
    CHECK(closestDistance(g, p) == doctest::Approx(std::abs(d)).epsilon(1e-9).scale(1e-9));
    CHECK(verticalDistance(g, p) >= closestDistance(g, p) - 1e-12);
    if (std::abs(d) > 0.05) CHECK(verticalDistance(g, p) > 1.02 * closestDistance(g, p));
    points.push_back(p);
    sumSq += d * d;
  }
  CHECK(surfaceRmse(g, points).value() == doctest::Approx(std::sqrt(sumSq / 200)).epsilon(1e-9));
  CHECK(!surfaceRmse(g, {}).has_value());  // no points: no error measured, not a perfect 0
  CHECK_THROWS_AS(surfaceRmse(g, {glm::dvec3(0, std::nan(""), 0)}), Error);
  HeightGrid bad = g;
  bad.heights.pop_back();
  CHECK_THROWS_AS(surfaceRmse(bad, points), Error);
  bad = g;
  bad.heights[3] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(surfaceRmse(bad, points), Error);
}

TEST_CASE("surface correlation: 1 for the true waves at any amplitude and offset, -1 upside down, 0 for unrelated water") {
  auto waves = [](double x, double y) { return 0.02 * std::sin(3 * x) + 0.01 * std::cos(2 * y + 0.5); };
  HeightGrid g = gridOf(41, 33, -1, -1, 1, 1, waves);
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<glm::dvec3> scaled, inverted, noisy;
  std::vector<double> heights, noise;
  for (int k = 0; k < 400; k++) {
    const double x = U(rng), y = U(rng), h = sampleHeight(g, x, y), e = 0.02 * U(rng);
    scaled.push_back({x, y, 0.3 * h + 5.0});  // a third of the amplitude, metres above
    inverted.push_back({x, y, -2 * h});
    noisy.push_back({x, y, h + e});
    heights.push_back(h);
    noise.push_back(e);
  }
  auto variance = [](const std::vector<double>& v) {
    double mean = 0, sum = 0;
    for (double a : v) mean += a / double(v.size());
    for (double a : v) sum += (a - mean) * (a - mean);
    return sum / double(v.size());
  };
  const double signal2 = variance(heights), noise2 = variance(noise);
  CHECK(surfaceCorrelation(g, scaled) == doctest::Approx(1).epsilon(1e-9));
  CHECK(surfaceCorrelation(g, inverted) == doctest::Approx(-1).epsilon(1e-9));
  // Independent noise of about the waves' size: near 1 / sqrt(1 + noise / signal), well under 1.
  const double expected = 1 / std::sqrt(1 + noise2 / signal2);
  CHECK(surfaceCorrelation(g, noisy) == doctest::Approx(expected).epsilon(0.15));
  CHECK(surfaceCorrelation(g, noisy) < 0.95);
  // On a symmetric lattice, water tilted along y over truth that varies along x only: exactly 0.
  HeightGrid alongX = gridOf(9, 9, -1, -1, 1, 1, [](double x, double) { return 0.1 * x; });
  std::vector<glm::dvec3> tiltedY;
  for (int i = -4; i <= 4; i++)
    for (int j = -4; j <= 4; j++) tiltedY.push_back({i / 4.0, j / 4.0, 0.05 * j / 4.0});
  CHECK(surfaceCorrelation(alongX, tiltedY) == doctest::Approx(0).scale(1e-12));
  // Flat learned water, or one point: no correlation to give.
  CHECK(std::isnan(surfaceCorrelation(g, {{0.1, 0.2, 0.0}, {0.3, -0.4, 0.0}})));
  CHECK(std::isnan(surfaceCorrelation(g, {{0.1, 0.2, 0.0}})));
}

TEST_CASE("surface distance on a curved surface agrees with a brute-force search") {
  HeightGrid g = gridOf(11, 9, -1, -1, 1, 1, [](double x, double y) { return 0.25 * std::sin(4 * x) * std::cos(3 * y); });
  const uint32_t seed = test::freshSeed();
  MESSAGE("seed " << seed << " (replay with REFRAX_TEST_SEED=" << seed << ")");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int sub = 40;  // samples per cell side for the brute force
  double worstGap = 0;  // largest brute - d, reported to show the margin to the bar
  for (int k = 0; k < 12; k++) {
    // at least 0.05 off the surface, and samples on every cell edge and vertex: the bilinear
    // surface has creases along the cell edges, and a closest point on a crease (or at a
    // vertex, under a peak) is then sampled along the crease only, so the brute force's error
    // stays second order in its spacing (about 1e-4 here) instead of up to half a spacing
    // times the crease angle (a CI run's point (0.378, 0.016, 0.523), closest to a vertex under
    // it: cell-centre samples came out 1.4e-3 long, lattice samples hit the vertex exactly)
    glm::dvec3 p(U(rng) * 0.9, U(rng) * 0.9, 0.0);
    double offset = U(rng);
    p.z = sampleHeight(g, p.x, p.y) + (offset < 0 ? -0.05 : 0.05) + 0.25 * offset;
    double brute = std::numeric_limits<double>::infinity();
    for (int j = 0; j <= (g.ny - 1) * sub; j++)
      for (int i = 0; i <= (g.nx - 1) * sub; i++) {
        double x = -1 + 2.0 * i / ((g.nx - 1) * sub), y = -1 + 2.0 * j / ((g.ny - 1) * sub);
        brute = std::min(brute, glm::length(p - glm::dvec3(x, y, sampleHeight(g, x, y))));
      }
    double d = closestDistance(g, p);
    INFO("point " << p.x << " " << p.y << " " << p.z << ": local search " << d << ", brute force " << brute);
    CHECK(d <= brute + 1e-12);
    worstGap = std::max(worstGap, brute - d);
    CHECK(d >= brute - 1e-3);
    CHECK(d <= verticalDistance(g, p) + 1e-12);
  }
  MESSAGE("largest brute force excess over the local search: " << worstGap);
}
