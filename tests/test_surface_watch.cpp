// The roughening watch (engine/surface/surface_watch.h): the seen water's shape against
// hand-computed values, and the verdict on series built to roughen or not.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>

#include "engine/base/error.h"
#include "engine/surface/surface_watch.h"

namespace refrax {
namespace {

// A plain 2 x 1 cell grid (3 x 2 vertices), spacing 0.5 m in x and 0.25 m in y.
GridLayout smallGrid() {
  GridLayout g;
  g.cellsX = 2;
  g.cellsY = 1;
  g.rowLength = 3;
  g.first = 0;
  g.spacingX = 0.5;
  g.spacingY = 0.25;
  return g;
}

std::vector<SurfaceWatchSample> series(int learnFrom, int last, int every, const std::function<double(double)>& slope,
                                       const std::function<double(double)>& loss) {
  std::vector<SurfaceWatchSample> s;
  for (int t = learnFrom + every; t <= last; t += every) {
    double u = double(t - learnFrom) / double(last - learnFrom);  // 0..1 over the learning
    SurfaceWatchSample w;
    w.step = t;
    w.loss = loss(u);
    w.shape.slopeRms = slope(u);
    s.push_back(w);
  }
  return s;
}

}  // namespace

TEST_CASE("surface watch: the seen water's RMS slope and height match hand-computed values, and unseen vertices do not count") {
  // Heights (row j = 0 then j = 1): 0, 0.1, 0.3 / 0.05, 0.1, 9 (the last vertex unseen).
  std::vector<float> h = {0.0f, 0.1f, 0.3f, 0.05f, 0.1f, 9.0f};
  std::vector<double> w = {1, 1, 1, 1, 1, 0};
  SurfaceShape s = measureSurfaceShape(h, smallGrid(), w);
  // Edges with both ends seen: x (0-1) 0.1/0.5, (1-2) 0.2/0.5, (3-4) 0.05/0.5; y (0-3) 0.05/0.25, (1-4) 0/0.25.
  double slopes[] = {0.2, 0.4, 0.1, 0.2, 0.0};
  double sum = 0;
  for (double v : slopes) sum += v * v;
  CHECK(s.slopeRms == doctest::Approx(std::sqrt(sum / 5)).epsilon(1e-6));
  double mean = (0.0 + 0.1 + 0.3 + 0.05 + 0.1) / 5, spread = 0;
  for (double v : {0.0, 0.1, 0.3, 0.05, 0.1}) spread += (v - mean) * (v - mean);
  CHECK(s.heightRms == doctest::Approx(std::sqrt(spread / 5)).epsilon(1e-6));

  // Weights weigh: doubling one vertex's weight moves the mean toward it.
  w[2] = 2;
  SurfaceShape weighted = measureSurfaceShape(h, smallGrid(), w);
  double wmean = (0.0 + 0.1 + 2 * 0.3 + 0.05 + 0.1) / 6, wspread = 0;
  const double vals[] = {0.0, 0.1, 0.3, 0.05, 0.1}, ws[] = {1, 1, 2, 1, 1};
  for (int k = 0; k < 5; k++) wspread += ws[k] * (vals[k] - wmean) * (vals[k] - wmean);
  CHECK(weighted.heightRms == doctest::Approx(std::sqrt(wspread / 6)).epsilon(1e-6));

  // Nothing seen: a flat answer, and mismatched sizes are refused.
  CHECK(measureSurfaceShape(h, smallGrid(), std::vector<double>(6, 0.0)).slopeRms == 0.0);
  CHECK_THROWS_AS(measureSurfaceShape(h, smallGrid(), std::vector<double>(5, 1.0)), Error);
}

TEST_CASE("surface watch: slopes growing while the loss stalls are roughening, growing while the loss falls, or flat, are not") {
  const int from = 100, last = 1500;
  auto flatLoss = [](double u) { return 0.10 + 0.001 * std::sin(40 * u); };  // noisy, not falling
  auto fallingLoss = [](double u) { return 0.20 * (1 - 0.5 * u); };          // -20% over the last third against the one before
  auto growing = [](double u) { return u < 1.0 / 3 ? 0.05 : 0.05 + 0.2 * (u - 1.0 / 3); };  // +0.133 in the window: +267%
  auto steady = [](double) { return 0.05; };

  const std::vector<SurfaceWatchSample> roughening = series(from, last, 15, growing, flatLoss);
  RougheningVerdict bad = judgeRoughening(roughening, from);
  CHECK(bad.judged);
  CHECK(bad.roughening);
  CHECK(bad.toStep == roughening.back().step);
  CHECK(bad.slopeAfter > bad.slopeBefore);
  CHECK(bad.text.find("roughened") != std::string::npos);

  RougheningVerdict learning = judgeRoughening(series(from, last, 15, growing, fallingLoss), from);
  CHECK(learning.judged);
  CHECK(!learning.roughening);
  CHECK(learning.lossAfter < learning.lossBefore);

  RougheningVerdict still = judgeRoughening(series(from, last, 15, steady, flatLoss), from);
  CHECK(still.judged);
  CHECK(!still.roughening);

  // Growth under the rule's 25%: not roughening.
  auto slight = [](double u) { return 0.05 * (1 + 0.15 * u); };
  CHECK(!judgeRoughening(series(from, last, 15, slight, flatLoss), from).roughening);

  // Too few samples to compare two windows: not judged, and no claim either way.
  RougheningVerdict few = judgeRoughening(series(from, last, 700, growing, flatLoss), from);
  CHECK(!few.judged);
  CHECK(!few.roughening);
  CHECK(!judgeRoughening({}, from).judged);
}

TEST_CASE("surface watch: the samples survive JSON, and a malformed file is refused by name") {
  std::vector<SurfaceWatchSample> s(2);
  s[0] = {10, 0.25, {0.125, 0.0625}};
  s[1] = {20, 0.5, {0.25, 0.03125}};
  std::vector<SurfaceWatchSample> back = surfaceWatchFromJson(surfaceWatchJson(s), "x");
  REQUIRE(back.size() == 2);
  CHECK(back[1].step == 20);
  CHECK(back[1].loss == 0.5);
  CHECK(back[1].shape.slopeRms == 0.25);
  CHECK(back[1].shape.heightRms == 0.03125);
  CHECK_THROWS_WITH_AS(surfaceWatchFromJson(nlohmann::json::object(), "RUN/surface_watch.json"),
                       doctest::Contains("RUN/surface_watch.json"), Error);
  CHECK_THROWS_WITH_AS(surfaceWatchFromJson(nlohmann::json::parse(R"([{"step": 1}])"), "RUN/surface_watch.json"),
                       doctest::Contains("RUN/surface_watch.json"), Error);
}

}  // namespace refrax
