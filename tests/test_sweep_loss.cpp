// The sweep loss (engine/train/sweep_loss.h) on a hand-built depth map: its dLoss/d(ray origin,
// direction) against central differences of the loss it returns, on rays landing on cells of
// different depths; the rays that cannot land count for nothing; and in a session, the water
// learns from it (a study option's plumbing: the surface's backward is the photometric one's).
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/train/sweep_loss.h"
#include "engine/train/train_session.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

// 7 x 6 cells of 0.1 m from (-0.35, -0.3), depths between -0.55 and -0.45, a smooth colour.
DepthMap handMap() {
  DepthMap m;
  m.cellsX = 7, m.cellsY = 6;
  m.xMin = -0.35, m.yMin = -0.3, m.cellSize = 0.1;
  for (uint32_t y = 0; y < m.cellsY; y++)
    for (uint32_t x = 0; x < m.cellsX; x++) {
      m.z.push_back(-0.5 + 0.05 * std::sin(1.3 * x + 0.7 * y));
      m.rgb.push_back(float(0.5 + 0.4 * std::sin(0.9 * x - 0.4 * y)));
      m.rgb.push_back(float(0.5 + 0.3 * std::cos(0.5 * x + 1.1 * y)));
      m.rgb.push_back(float(0.2 + 0.05 * x));
    }
  return m;
}

double lossOf(const DepthMap& map, const Image& image, const GpuRay& ray) {
  SweepView v{{ray}, &image};
  std::vector<GpuRayGrad> g;
  size_t used = 0;
  return sweepTextureLoss(v, map, 1.0, g, used);
}

}  // namespace

TEST_CASE("sweep loss: dLoss/d(origin, direction) matches central differences") {
  const DepthMap map = handMap();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked = 0;
  for (int trial = 0; trial < 40; trial++) {
    GpuRay r{};
    r.origin[0] = float(0.2 * u(rng)), r.origin[1] = float(0.15 * u(rng)), r.origin[2] = float(0.02 * u(rng));
    double d[3] = {0.3 * u(rng), 0.3 * u(rng), -1.0};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int a = 0; a < 3; a++) r.dir[a] = float(d[a] / len);
    Image image;
    image.width = 1, image.height = 1, image.channels = 3;
    image.pixels = {float(0.5 + 0.4 * u(rng)), float(0.5 + 0.4 * u(rng)), float(0.5 + 0.4 * u(rng))};
    SweepView v{{r}, &image};
    std::vector<GpuRayGrad> g;
    size_t used = 0;
    sweepTextureLoss(v, map, 1.0, g, used);
    REQUIRE(g.size() == 1);
    if (used == 0) continue;
    checked++;
    // float rays: a step of 1e-4 (a 1e-6 step would be under the float's resolution)
    const double h = 1e-4;
    for (int a = 0; a < 6; a++) {
      GpuRay plus = r, minus = r;
      float* p = a < 3 ? &plus.origin[a] : &plus.dir[a - 3];
      float* m = a < 3 ? &minus.origin[a] : &minus.dir[a - 3];
      *p += float(h), *m -= float(h);
      const double fd = (lossOf(map, image, plus) - lossOf(map, image, minus)) / (double(*p) - double(*m));
      const double an = a < 3 ? g[0].dOrigin[a] : g[0].dDir[a - 3];
      CAPTURE(trial);
      CAPTURE(a);
      CHECK(an == doctest::Approx(fd).epsilon(2e-3).scale(1e-2));
    }
  }
  CHECK(checked >= 30);  // most rays land on the map
}

TEST_CASE("sweep loss: rays that cannot land count for nothing, and the weight scales the gradient") {
  const DepthMap map = handMap();
  Image image;
  image.width = 4, image.height = 1, image.channels = 3;
  image.pixels.assign(12, 0.9f);
  std::vector<GpuRay> rays(4, GpuRay{});
  rays[0].dir[2] = -1;                     // straight down at the centre: lands
  rays[1].dir[2] = 1;                      // up
  rays[2].origin[2] = -0.8f, rays[2].dir[2] = -1;  // starts under the floor
  rays[3].origin[0] = 5, rays[3].dir[2] = -1;      // off the map
  SweepView v{rays, &image};
  std::vector<GpuRayGrad> one, three;
  size_t used = 0;
  const double loss = sweepTextureLoss(v, map, 1.0, one, used);
  CHECK(used == 1);
  CHECK(loss > 0);
  sweepTextureLoss(v, map, 3.0, three, used);
  for (int a = 0; a < 3; a++) {
    CHECK(three[0].dOrigin[a] == doctest::Approx(3 * one[0].dOrigin[a]));
    for (size_t i = 1; i < 4; i++) CHECK(one[i].dOrigin[a] == 0.0f);
  }
}

GPU_TEST_CASE("sweep loss in training: a rough water grows more consistent with it than without it") {
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 30, 500, 16, 1, d);
  c.mlpInitRange = 0.01;  // a rough start: the views agree worse through it than through flat water
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 3e-3;
  auto ratioAfter = [&](double weight) {
    c.sweepLoss = weight;
    c.sweepLossEvery = 2;
    auto s = createTrainSession(ctx, c, d);
    for (int k = 0; k < c.steps; k++) trainStep(*s);
    CHECK(s->log.sweepLosses.size() == (weight > 0 ? size_t(c.steps / 2) : 0u));
    for (const auto& p : s->log.sweepLosses) CHECK((p.rays > 0 && p.perRay > 0));
    const SweepAgreement a = agreementWithFlatWater(*s);
    REQUIRE(a.cells > 100);
    return a.cost / a.reference;
  };
  const double without = ratioAfter(0), with = ratioAfter(10);
  MESSAGE("sweep cost against flat water's after 30 steps from a rough water: " << without << " without the sweep loss, " << with << " with it");
  CHECK(with < 0.8 * without);
}

GPU_TEST_CASE("sweep loss only: the images' gradient reaches the Gaussians, not the water") {
  // --sweep-loss-only: with the sweep loss never due in these steps (every millionth surface
  // step) and no prior or anchor, nothing else may move the water; without the flag the images
  // move it. The Gaussians learn either way.
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 12, 300, 16, 1, d);
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 3e-3;
  c.surfaceSmoothness = 0;
  c.levelPrior = 0;
  c.anchorMeanHeight = false;
  c.sweepLoss = 1;
  c.sweepLossEvery = 1000000;
  auto largestChange = [](const std::vector<float>& a, const std::vector<float>& b) {
    double d = 0;
    for (size_t i = 0; i < a.size(); i++) d = std::max(d, std::abs(double(a[i]) - double(b[i])));
    return d;
  };
  auto changes = [&](bool only) {
    c.sweepLossOnly = only;
    validateTrainConfig(c);
    auto s = createTrainSession(ctx, c, d);
    const std::vector<float> water = downloadWeights(ctx, *s->model.height);
    const std::vector<float> gaussians = s->model.gaussians.params;
    for (int k = 0; k < c.steps; k++) trainStep(*s);
    pullGaussians(*s);
    CHECK(s->log.sweepLosses.empty());
    return std::make_pair(largestChange(downloadWeights(ctx, *s->model.height), water), largestChange(s->model.gaussians.params, gaussians));
  };
  const auto [waterWith, gaussiansWith] = changes(false);
  const auto [waterOnly, gaussiansOnly] = changes(true);
  MESSAGE("largest water weight change: " << waterWith << " from the images, " << waterOnly << " with --sweep-loss-only");
  CHECK(waterWith > 1e-4);
  CHECK(waterOnly == 0);
  CHECK(gaussiansWith > 1e-4);
  CHECK(gaussiansOnly > 1e-4);
  c.sweepLoss = 0;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--sweep-loss-only needs --sweep-loss"), Error);
}

TEST_CASE("sweep loss: the agreed colours are the mean of each view's mean where enough views land") {
  DepthMap map = handMap();
  const std::vector<float> before = map.rgb;
  // Straight down at (0.05, 0.05): cell (4, 3). View a lands twice there (0.2 and 0.4), view b
  // once (0.9): the agreed red is (0.3 + 0.9) / 2, not the rays' mean 0.5.
  auto view = [](std::vector<float> reds) {
    Image im;
    im.width = int(reds.size()), im.height = 1, im.channels = 3;
    for (float r : reds) im.pixels.insert(im.pixels.end(), {r, 0.5f, 0.5f});
    return im;
  };
  GpuRay down{};
  down.origin[0] = 0.05f, down.origin[1] = 0.05f, down.dir[2] = -1;
  const Image a = view({0.2f, 0.4f}), b = view({0.9f});
  AgreedColours colours;
  addViewColours(SweepView{{down, down}, &a}, map, colours);
  addViewColours(SweepView{{down}, &b}, map, colours);
  const size_t cell = 3 * map.cellsX + 4;
  setAgreedColours(map, colours, 3);  // two views: under the minimum, unchanged
  CHECK(map.rgb == before);
  setAgreedColours(map, colours, 2);
  CHECK(map.rgb[cell * 3] == doctest::Approx(0.6));
  CHECK(map.rgb[cell * 3 + 1] == doctest::Approx(0.5));
  for (size_t c = 0; c < before.size() / 3; c++)
    if (c != cell) CHECK(map.rgb[c * 3] == before[c * 3]);
}
