// MCMC densification (engine/gaussian/mcmc.h): the shared density and sigma factor against
// what they promise (k copies stacked along a ray let through what the one did, and integrate
// to the one's opacity), relocation, growth, the position noise, and a training run with it.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/mcmc.h"
#include "engine/io/json_io.h"
#include "engine/optim/adam.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

// A set of Gaussians with the given densities, isotropic sigma, distinct means.
GaussianSet gaussiansWithDensities(const std::vector<double>& densities, double sigma = 0.02) {
  GaussianSet set;
  set.params.assign(densities.size() * kGaussianFloats, 0.0f);
  for (size_t i = 0; i < densities.size(); i++) {
    float* g = set.at(i);
    g[f32::kGaussMean + 0] = float(i);
    g[f32::kGaussMean + 1] = float(0.5 * double(i));
    g[f32::kGaussMean + 2] = -1.0f;
    g[f32::kGaussRotation] = 1.0f;
    for (int a = 0; a < 3; a++) g[f32::kGaussLogScale + a] = float(std::log(sigma));
    g[f32::kGaussLogitDensity] = float(std::log(densities[i] / (1.0 - densities[i])));
    g[f32::kGaussSH] = float(i) * 0.1f;  // tells the rows apart
  }
  return set;
}

double densityAt(const GaussianSet& set, size_t i) { return f64::sigmoidOf(double(set.at(i)[f32::kGaussLogitDensity])); }

}  // namespace

TEST_CASE("mcmc: k copies of the shared density and sigmas let through and integrate to what the one did" * doctest::test_suite("one-backend")) {
  for (double o : {0.01, 0.3, 0.9, 0.999})
    for (int k = 1; k <= 12; k++) {
      CAPTURE(o);
      CAPTURE(k);
      const double shared = mcmcSharedDensity(o, k);
      CHECK(1.0 - std::pow(1.0 - shared, k) == doctest::Approx(o).epsilon(1e-12));
      // Along a ray through the centre the one has alpha o exp(-x^2/2); the k copies, each
      // o' exp(-x^2 / 2c^2), composite to 1 - (1 - o' exp(-x^2 / 2c^2))^k. Their integrals
      // over x must agree (Eq. 9), checked here by quadrature, not by the series.
      const double c = mcmcSigmaFactor(o, k);
      double one = 0, copies = 0;
      const double dx = 1e-3;
      for (double x = -12; x <= 12; x += dx) {
        one += o * std::exp(-0.5 * x * x) * dx;
        copies += (1.0 - std::pow(1.0 - shared * std::exp(-0.5 * x * x / (c * c)), k)) * dx;
      }
      CHECK(copies == doctest::Approx(one).epsilon(1e-6));
      if (k == 1) CHECK(c == doctest::Approx(1.0));
    }
}

TEST_CASE("mcmc: dead Gaussians become copies of live ones, which share their mass, and the Adam rows restart" * doctest::test_suite("one-backend")) {
  // Rows 1, 3, 4 are dead; row 2 is the only live one besides row 0, whose density is 0.9.
  GaussianSet set = gaussiansWithDensities({0.9, 0.001, 0.2, 0.004, 0.0001});
  McmcConfig config;
  config.growFraction = 0;
  std::mt19937 rng(5);
  std::vector<uint32_t> rowMap;
  const GaussianSet before = set;
  McmcStats stats = mcmcDensify(set, config, rng, rowMap);
  CHECK(stats.relocated == 3);
  CHECK(stats.added == 0);
  REQUIRE(set.count() == 5);
  REQUIRE(rowMap.size() == 5);
  // Every row now holds one of the live rows' colours; the copies of a source carry its
  // shared density, and together with it they let through what it did.
  int copiesOf[2] = {0, 0};
  for (size_t i = 0; i < 5; i++) {
    const float colour = set.at(i)[f32::kGaussSH];
    CHECK((colour == before.at(0)[f32::kGaussSH] || colour == before.at(2)[f32::kGaussSH]));
    copiesOf[colour == before.at(0)[f32::kGaussSH] ? 0 : 1]++;
  }
  const size_t sources[2] = {0, 2};
  for (int s = 0; s < 2; s++) {
    const int k = copiesOf[s];
    const double o = densityAt(before, sources[s]);
    CHECK(densityAt(set, sources[s]) == doctest::Approx(mcmcSharedDensity(o, k)).epsilon(1e-5));
    const double sigma = std::exp(double(set.at(sources[s])[f32::kGaussLogScale]));
    CHECK(sigma == doctest::Approx(0.02 * mcmcSigmaFactor(o, k)).epsilon(1e-5));
    CHECK((rowMap[sources[s]] == kNewRow) == (k > 1));
  }
  for (size_t dead : {1, 3, 4}) CHECK(rowMap[dead] == kNewRow);

  // The same draws from the same rng state.
  GaussianSet again = before;
  std::mt19937 rng2(5);
  std::vector<uint32_t> rowMap2;
  mcmcDensify(again, config, rng2, rowMap2);
  CHECK(again.params == set.params);
  CHECK(rowMap2 == rowMap);
}

TEST_CASE("mcmc: the count grows by the fraction up to the cap, and nothing changes when no Gaussian is live or none is left live" * doctest::test_suite("one-backend")) {
  std::vector<double> densities(100, 0.5);
  GaussianSet set = gaussiansWithDensities(densities);
  McmcConfig config;
  config.maxGaussians = 1000;
  std::mt19937 rng(1);
  std::vector<uint32_t> rowMap;
  McmcStats stats = mcmcDensify(set, config, rng, rowMap);
  CHECK(stats.added == 5);
  CHECK(set.count() == 105);
  REQUIRE(rowMap.size() == 105);
  for (size_t i = 100; i < 105; i++) CHECK(rowMap[i] == kNewRow);
  size_t kept = 0;
  for (size_t i = 0; i < 100; i++) kept += rowMap[i] == uint32_t(i);
  CHECK(kept >= 95);  // at most 5 sources restarted

  config.maxGaussians = 107;
  stats = mcmcDensify(set, config, rng, rowMap);
  CHECK(stats.added == 2);
  CHECK(set.count() == 107);
  stats = mcmcDensify(set, config, rng, rowMap);
  CHECK(stats.added == 0);

  GaussianSet dead = gaussiansWithDensities({0.001, 0.002});
  const GaussianSet deadBefore = dead;
  stats = mcmcDensify(dead, config, rng, rowMap);
  CHECK(stats.relocated == 0);
  CHECK(dead.params == deadBefore.params);
  CHECK(rowMap == std::vector<uint32_t>{0, 1});

  // One barely live Gaussian shares its density with the dead one, and both copies fall under
  // the dead line: growth then has no live row to copy and adds none.
  GaussianSet barely = gaussiansWithDensities({0.0055, 0.001});
  config.growFraction = 1;
  stats = mcmcDensify(barely, config, rng, rowMap);
  CHECK(stats.relocated == 1);
  CHECK(densityAt(barely, 0) < config.minDensity);
  CHECK(stats.added == 0);
  CHECK(barely.count() == 2);
}

TEST_CASE("mcmc: the position noise moves the nearly transparent by lr x scale x sigma^2 and leaves the opaque in place" * doctest::test_suite("one-backend")) {
  const double sigma = 0.05, lr = 1e-4;
  std::vector<double> densities(2000, 1e-4);
  densities[0] = 0.9;
  GaussianSet set = gaussiansWithDensities(densities, sigma);
  const GaussianSet before = set;
  McmcConfig config;
  std::mt19937 rng(3);
  mcmcPositionNoise(set, config, lr, rng);
  for (int a = 0; a < 3; a++) CHECK(std::abs(set.at(0)[f32::kGaussMean + a] - before.at(0)[f32::kGaussMean + a]) < 1e-6);
  // Isotropic sigma: each axis moves by N(0, (lr * scale * gate * sigma^2)^2), gate ~ 0.5 at 1e-4.
  const double gate = f64::sigmoidOf(100.0 * (0.005 - 1e-4));
  const double expected = lr * 5e5 * gate * sigma * sigma;
  double sumSquares = 0;
  for (size_t i = 1; i < set.count(); i++)
    for (int a = 0; a < 3; a++) {
      const double d = double(set.at(i)[f32::kGaussMean + a]) - double(before.at(i)[f32::kGaussMean + a]);
      sumSquares += d * d;
    }
  const double measured = std::sqrt(sumSquares / (3.0 * double(set.count() - 1)));
  CHECK(measured == doctest::Approx(expected).epsilon(0.05));
}

TEST_CASE("train: --densify-strategy mcmc grows the count 5% per densification, prunes nothing, and survives config.json") {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string run = (dir / "mcmc");
  nlohmann::json metrics = test::trainAndReadMetrics(data, run,
                                                     "--recipe reference --steps 40 --gaussians 300 --max-gaussians 10000 --patch 16 --densify-strategy mcmc "
                                                     "--densify-from 10 --densify-every 10 --densify-until 30 --checkpoint-every 0");
  // 300 -> 315 -> 330 -> 346 at steps 10, 20, 30 (5%, rounded down); none is ever removed.
  CHECK(metrics["gaussians"].get<int>() == 346);
  CHECK(readJson(run + "/config.json")["densify_strategy"] == "mcmc");
}
