// The height-grid source (the known-water oracle's water where it has no closed form) against
// sampleHeight in double: bilinear inside, clamped to the edge outside, NaN for a point that
// is not finite. And the known water scaled about its level (--known-water-scale).
#include <cmath>
#include <limits>

#include "engine/dataset/ground_truth.h"
#include "engine/height/analytic_height.h"
#include "engine/height/grid_height.h"
#include "engine/loss/metrics.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

GPU_TEST_CASE("grid heights: the device samples a height grid as sampleHeight does, clamped outside its box") {
  // A grid neither square nor on a square box, so that swapped axes or rows read wrong heights.
  HeightGrid g;
  g.nx = 37;
  g.ny = 23;
  g.xMin = -1.3;
  g.xMax = 0.9;
  g.yMin = -0.4;
  g.yMax = 0.7;
  std::uniform_real_distribution<double> h(-0.05, 0.05);
  for (int k = 0; k < g.nx * g.ny; k++) g.heights.push_back(h(rng));
  const double box[4] = {g.xMin, g.yMin, g.xMax, g.yMax};
  GridHeightField field = createGridHeightField(ctx, uint32_t(g.nx), uint32_t(g.ny), box, g.heights);

  std::uniform_real_distribution<double> x(-1.6, 1.2), y(-0.7, 1.0);  // about a tenth of them outside
  std::vector<float> points;
  for (int k = 0; k < 4000; k++) {
    points.push_back(float(x(rng)));
    points.push_back(float(y(rng)));
  }
  // The corners and edges exactly (the last cell's upper end).
  for (double px : {g.xMin, g.xMax})
    for (double py : {g.yMin, g.yMax}) {
      points.push_back(float(px));
      points.push_back(float(py));
    }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  points.push_back(nan);
  points.push_back(0.1f);
  const uint32_t n = uint32_t(points.size() / 2);
  Buffer pointBuffer = createBufferFrom(ctx, points);
  Buffer heights = createBuffer(ctx, size_t(n) * 4);
  HeightSource source = heightSource(field);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { source.evaluate(cb, pointBuffer, n, heights); });
  std::vector<float> out = downloadVector<float>(ctx, heights, n);

  double worst = 0;
  for (uint32_t k = 0; k + 1 < n; k++) {
    const double expect = sampleHeight(g, double(points[2 * k]), double(points[2 * k + 1]));
    worst = std::max(worst, std::abs(double(out[k]) - expect));
  }
  INFO("worst difference " << worst);
  CHECK(worst <= 1e-6);  // float heights of 0.05 m and float fractions: ~1e-8 measured
  CHECK(std::isnan(out[n - 1]));

  // Grids it cannot sample are refused: one row, a count that does not match, an empty box.
  CHECK_THROWS_AS(createGridHeightField(ctx, uint32_t(g.nx), 1, box, std::vector<double>(size_t(g.nx), 0.0)), Error);
  CHECK_THROWS_AS(createGridHeightField(ctx, uint32_t(g.nx), uint32_t(g.ny), box, std::vector<double>(7, 0.0)), Error);
  const double empty[4] = {0.5, 0.0, 0.5, 1.0};
  CHECK_THROWS_AS(createGridHeightField(ctx, uint32_t(g.nx), uint32_t(g.ny), empty, g.heights), Error);
}

TEST_CASE("known water scaled: the waves' and ripples' amplitudes, or a height map about its mean, the base kept") {
  KnownWaterTruth waves;
  waves.waves = AnalyticWaves{};
  waves.waves->base = 0.2f;
  waves.waves->waves[0][0] = 0.01f, waves.waves->waves[0][1] = 3;
  waves.waves->waves[1][0] = -0.02f, waves.waves->waves[1][1] = 5, waves.waves->sigma[1] = 0.3f;
  const AnalyticWaves before = *waves.waves;
  scaleKnownWater(waves, 0.5);
  for (double x : {-0.3, 0.1, 0.4})
    CHECK(analyticHeightRef(*waves.waves, x, 0.2) == doctest::Approx(0.2 + 0.5 * (analyticHeightRef(before, x, 0.2) - 0.2)).epsilon(1e-6));
  KnownWaterTruth grid;
  grid.grid = HeightGrid{3, 2, 0, 0, 1, 1, {1.0, 2.0, 3.0, 4.0, 5.0, 9.0}};  // mean 4
  scaleKnownWater(grid, 2.0);
  CHECK(grid.grid->heights == std::vector<double>{-2.0, 0.0, 2.0, 4.0, 6.0, 14.0});
  scaleKnownWater(grid, 0.0);
  CHECK(grid.grid->heights == std::vector<double>(6, 4.0));
}
