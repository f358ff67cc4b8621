// Densification on the host: hand-built sets where every clone, split and prune is known,
// split children drawn from the parent's Gaussian (moments in its own frame), the row map
// against the output, the cap, the schedule, density reset/decay against the double formulas,
// and the device-set entry point against the host one.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "engine/gaussian/densify.h"
#include "engine/gaussian/densify_device.h"
#include "engine/gaussian/gaussian_adam.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

double logitOf(double p) { return std::log(p / (1 - p)); }
double sigmoidOf(double x) { return 1 / (1 + std::exp(-x)); }

// One Gaussian: mean, sigmas, density, rotation (w x y z), a colour tag in the SH.
void addGaussian(GaussianSet& set, glm::vec3 mean, glm::vec3 sigma, float density, glm::vec4 q = {1, 0, 0, 0}, float tag = 0) {
  size_t i = set.count();
  set.params.resize(set.params.size() + kGaussianFloats, 0.0f);
  float* g = set.at(i);
  for (int a = 0; a < 3; a++) {
    g[f32::kGaussMean + a] = mean[a];
    g[f32::kGaussLogScale + a] = std::log(sigma[a]);
  }
  for (int a = 0; a < 4; a++) g[f32::kGaussRotation + a] = q[a];
  g[f32::kGaussLogitDensity] = float(logitOf(density));
  for (uint32_t k = 0; k < 48; k++) g[f32::kGaussSH + k] = tag + 0.01f * float(k);
}

bool sameRow(const GaussianSet& a, size_t i, const GaussianSet& b, size_t j) {
  return std::memcmp(a.at(i), b.at(j), kGaussianFloats * sizeof(float)) == 0;
}

// Every row the map says continues an old row holds that row's parameters unchanged;
// surviving rows keep their order; new rows are the rest.
void checkRowMap(const GaussianSet& before, const GaussianSet& after, const std::vector<uint32_t>& rowMap, uint32_t expectedNew) {
  REQUIRE(rowMap.size() == after.count());
  uint32_t fresh = 0;
  int64_t last = -1;
  for (size_t i = 0; i < rowMap.size(); i++) {
    if (rowMap[i] == kNewRow) {
      fresh++;
      continue;
    }
    REQUIRE(rowMap[i] < before.count());
    CHECK(int64_t(rowMap[i]) > last);
    last = rowMap[i];
    CHECK(sameRow(after, i, before, rowMap[i]));
  }
  CHECK(fresh == expectedNew);
}

// A split child's parameters other than mean and scale equal the parent's; the scale is / 1.6.
void checkSplitChild(const GaussianSet& after, size_t child, const GaussianSet& before, size_t parent) {
  const float* c = after.at(child);
  const float* p = before.at(parent);
  for (uint32_t k = 0; k < kGaussianFloats; k++) {
    if (k >= f32::kGaussLogScale && k < f32::kGaussLogScale + 3) CHECK(c[k] == doctest::Approx(p[k] - std::log(1.6)).epsilon(1e-6));
    else if (k >= f32::kGaussMean + 3 || k < f32::kGaussMean) CHECK(c[k] == p[k]);
  }
}

}  // namespace

TEST_CASE("densify: clones, splits and prunes of a hand-built set") {
  DensifyConfig config;  // extent 1: clone up to sigma 0.015, gradient threshold 3e-4
  GaussianSet set;
  std::vector<float> stats;
  auto add = [&](glm::vec3 sigma, float density, float sum, float hits, float tag) {
    addGaussian(set, glm::vec3(tag, 0, -0.5f), sigma, density, glm::vec4(0.9f, 0.1f, -0.2f, 0.3f), tag);
    stats.push_back(sum);
    stats.push_back(hits);
  };
  add(glm::vec3(0.01f), 0.5f, 4e-3f, 10, 0);                          // 0: clone (mean 4e-4)
  add(glm::vec3(0.02f), 0.5f, 4e-3f, 10, 1);                          // 1: split
  add(glm::vec3(0.01f), 0.5f, 2e-3f, 10, 2);                          // 2: below threshold, kept
  add(glm::vec3(0.01f), 0.004f, 1e-2f, 1, 3);                         // 3: pruned (density), not cloned
  add(glm::vec3(0.01f), 0.5f, 0, 0, 4);                               // 4: never hit, kept
  add(glm::vec3(0.014f, 0.016f, 0.001f), 0.9f, 1e-3f, 2, 5);          // 5: split (largest sigma 0.016)
  add(glm::vec3(0.3f), 0.5f, 0, 0, 6);                                // 6: too large, but only pruned from step 3000
  const GaussianSet before = set;

  std::mt19937 rng(7);
  std::vector<uint32_t> rowMap;
  DensifyStats s = densify(set, stats, config, 600, rng, rowMap);
  CHECK(s.before == 7);
  CHECK(s.cloned == 1);
  CHECK(s.split == 2);
  CHECK(s.prunedLowDensity == 1);
  CHECK(s.prunedLarge == 0);
  CHECK(s.cappedOut == 0);
  REQUIRE(s.after == 9);  // 7 - 1 pruned - 2 split parents + 1 clone + 4 children
  REQUIRE(set.count() == 9);
  const std::vector<uint32_t> expected = {0, 2, 4, 6, kNewRow, kNewRow, kNewRow, kNewRow, kNewRow};
  CHECK(rowMap == expected);
  checkRowMap(before, set, rowMap, 5);
  CHECK(sameRow(set, 4, before, 0));  // the clone is an exact copy
  checkSplitChild(set, 5, before, 1);
  checkSplitChild(set, 6, before, 1);
  checkSplitChild(set, 7, before, 5);
  checkSplitChild(set, 8, before, 5);
  // Children of the same parent differ from each other and from the parent's mean.
  CHECK(set.at(5)[0] != set.at(6)[0]);
  CHECK(set.at(7)[0] != before.at(5)[0]);
}

TEST_CASE("densify: only what the step is due for") {
  DensifyConfig config;
  GaussianSet set;
  std::vector<float> stats;
  addGaussian(set, glm::vec3(0), glm::vec3(0.01f), 0.5f);  // clone candidate
  stats.insert(stats.end(), {1.0f, 1.0f});
  addGaussian(set, glm::vec3(0), glm::vec3(0.01f), 0.001f);  // prune candidate
  stats.insert(stats.end(), {0.0f, 0.0f});
  addGaussian(set, glm::vec3(0), glm::vec3(0.5f), 0.5f);  // too large from step 3000
  stats.insert(stats.end(), {0.0f, 0.0f});
  const GaussianSet before = set;
  std::mt19937 rng(1);
  std::vector<uint32_t> rowMap;

  SUBCASE("neither due: the identity") {
    DensifyStats s = densify(set, stats, config, 650, rng, rowMap);
    CHECK(s.after == 3);
    CHECK(set.params == before.params);
    CHECK(rowMap == std::vector<uint32_t>{0, 1, 2});
  }
  SUBCASE("prune only") {
    DensifyStats s = densify(set, stats, config, 700, rng, rowMap);
    CHECK(s.cloned == 0);
    CHECK(s.prunedLowDensity == 1);
    CHECK(rowMap == std::vector<uint32_t>{0, 2});
  }
  SUBCASE("prune with the size test from step 3000, densify too") {
    DensifyStats s = densify(set, stats, config, 3000, rng, rowMap);
    CHECK(s.prunedLowDensity == 1);
    CHECK(s.prunedLarge == 1);
    CHECK(s.cloned == 1);
    CHECK(rowMap == std::vector<uint32_t>{0, kNewRow});
    checkRowMap(before, set, rowMap, 1);
  }
  SUBCASE("after densifyUntil only pruning runs") {
    config.densifyUntil = 2000;
    config.pruneUntil = 4000;
    DensifyStats s = densify(set, stats, config, 2100, rng, rowMap);
    CHECK(s.cloned == 0);
    CHECK(s.after == 2);
  }
}

TEST_CASE("densify: schedule follows from, until and interval") {
  DensifyConfig c;
  CHECK_FALSE(densifyDue(c, 300));
  CHECK_FALSE(densifyDue(c, 500));
  CHECK(densifyDue(c, 600));
  CHECK_FALSE(densifyDue(c, 700));
  CHECK(densifyDue(c, 15000));
  CHECK_FALSE(densifyDue(c, 15300));
  CHECK(pruneDue(c, 500));
  CHECK(pruneDue(c, 700));
  CHECK_FALSE(pruneDue(c, 750));
  CHECK_FALSE(densityResetDue(c, 0));
  CHECK(densityResetDue(c, 3000));
  CHECK(densityResetDue(c, 6000));
  CHECK_FALSE(densityResetDue(c, 6050));
  CHECK(densityDecayDue(c, 50));
  CHECK_FALSE(densityDecayDue(c, 75));
}

TEST_CASE("densify: the cap takes the largest statistics first") {
  DensifyConfig config;
  GaussianSet set;
  std::vector<float> stats;
  const float grads[5] = {1e-3f, 5e-3f, 2e-3f, 4e-3f, 3e-3f};
  for (int i = 0; i < 5; i++) {
    addGaussian(set, glm::vec3(float(i), 0, 0), glm::vec3(i % 2 ? 0.05f : 0.01f), 0.5f);  // odd rows split, even rows clone
    stats.insert(stats.end(), {grads[i], 1.0f});
  }
  const GaussianSet before = set;
  std::mt19937 rng(3);
  std::vector<uint32_t> rowMap;
  config.maxGaussians = 7;
  DensifyStats s = densify(set, stats, config, 600, rng, rowMap);
  // Taken in order 1 (split), 3 (split); then the cap is reached.
  CHECK(s.after == 7);
  CHECK(s.split == 2);
  CHECK(s.cloned == 0);
  CHECK(s.cappedOut == 3);
  CHECK(rowMap == std::vector<uint32_t>{0, 2, 4, kNewRow, kNewRow, kNewRow, kNewRow});
  checkRowMap(before, set, rowMap, 4);

  SUBCASE("a set already at or over the cap does not grow") {
    config.maxGaussians = 3;
    GaussianSet again = before;
    s = densify(again, stats, config, 600, rng, rowMap);
    CHECK(s.after == 5);
    CHECK(s.cappedOut == 5);
    CHECK(again.params == before.params);
  }
}

TEST_CASE("densify: split children follow the parent's distribution") {
  // 3000 identical anisotropic, rotated parents, all split: 6000 children. In the parent's
  // frame, (R^T (child - mean)) / sigma must be standard normal per axis and uncorrelated.
  DensifyConfig config;
  const glm::vec3 mean(0.3f, -0.2f, -0.6f), sigma(0.08f, 0.03f, 0.02f);
  const glm::vec4 q = glm::normalize(glm::vec4(0.8f, 0.3f, -0.4f, 0.2f));
  GaussianSet set;
  std::vector<float> stats;
  const int parents = 3000;
  for (int i = 0; i < parents; i++) {
    addGaussian(set, mean, sigma, 0.5f, q);
    stats.insert(stats.end(), {1.0f, 1.0f});
  }
  std::mt19937 rng(12345);
  std::vector<uint32_t> rowMap;
  DensifyStats s = densify(set, stats, config, 600, rng, rowMap);
  REQUIRE(s.split == parents);
  REQUIRE(set.count() == 2 * parents);
  glm::dmat3 R = f64::rotationOf(glm::dvec4(q));
  glm::dvec3 sum(0);
  glm::dmat3 second(0);
  for (size_t i = 0; i < set.count(); i++) {
    glm::dvec3 x = glm::dvec3(set.at(i)[0], set.at(i)[1], set.at(i)[2]) - glm::dvec3(mean);
    glm::dvec3 z = (glm::transpose(R) * x) / glm::dvec3(sigma);
    sum += z;
    second += glm::outerProduct(z, z);
  }
  const double n = double(set.count());
  for (int a = 0; a < 3; a++) {
    CHECK(std::abs(sum[a] / n) < 0.06);                 // 4.6 standard errors
    CHECK(second[a][a] / n == doctest::Approx(1.0).epsilon(0.09));
    for (int b = 0; b < a; b++) CHECK(std::abs(second[a][b] / n) < 0.06);
  }
  // Deterministic for a seed, different for another.
  GaussianSet a, b, c;
  for (int i = 0; i < 4; i++) {
    addGaussian(a, mean, sigma, 0.5f, q);
  }
  b = a;
  c = a;
  std::vector<float> st(8, 1.0f);
  std::mt19937 r1(99), r2(99), r3(100);
  densify(a, st, config, 600, r1, rowMap);
  densify(b, st, config, 600, r2, rowMap);
  densify(c, st, config, 600, r3, rowMap);
  CHECK(a.params == b.params);
  CHECK(a.params != c.params);
}

TEST_CASE("densify: random sets keep the row map and the counts consistent") {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(0, 1);
  for (int trial = 0; trial < 5; trial++) {
    GaussianSet set;
    std::vector<float> stats;
    for (int i = 0; i < 400; i++) {
      addGaussian(set, glm::vec3(u(rng), u(rng), u(rng)), glm::vec3(0.002f + 0.04f * u(rng)), 0.001f + 0.99f * u(rng), {1, 0, 0, 0}, float(i));
      stats.insert(stats.end(), {1e-3f * u(rng), float(int(3 * u(rng)))});
    }
    const GaussianSet before = set;
    std::vector<uint32_t> rowMap;
    DensifyConfig config;
    config.maxGaussians = 430;
    DensifyStats s = densify(set, stats, config, 600, rng, rowMap);
    CHECK(s.after == s.before - s.prunedLowDensity - s.prunedLarge - s.split + s.cloned + 2 * s.split);
    CHECK(s.after <= config.maxGaussians);
    checkRowMap(before, set, rowMap, s.cloned + 2 * s.split);
    for (size_t i = 0; i < set.count(); i++) CHECK(sigmoidOf(set.at(i)[f32::kGaussLogitDensity]) >= config.minDensity);
  }
}

TEST_CASE("densify: density reset and decay on the logits") {
  DensifyConfig config;
  GaussianSet set;
  const double densities[] = {1e-12, 1e-5, 0.004, 0.01, 0.3, 0.999, 1 - 1e-7};
  for (double d : densities) addGaussian(set, glm::vec3(0), glm::vec3(0.01f), float(d));
  set.at(6)[f32::kGaussLogitDensity] = 40.0f;  // a logit whose sigmoid is 1 in double
  GaussianSet reset = set, decayed = set;
  densityReset(reset, config);
  densityDecay(decayed, config);
  for (size_t i = 0; i < set.count(); i++) {
    double p = sigmoidOf(set.at(i)[f32::kGaussLogitDensity]);
    CHECK(sigmoidOf(reset.at(i)[f32::kGaussLogitDensity]) == doctest::Approx(std::min(p, 0.01)).epsilon(1e-5));
    CHECK(sigmoidOf(decayed.at(i)[f32::kGaussLogitDensity]) == doctest::Approx(0.99 * p).epsilon(1e-5));
    CHECK(std::isfinite(decayed.at(i)[f32::kGaussLogitDensity]));
    for (uint32_t k = 0; k < kGaussianFloats; k++)
      if (k != f32::kGaussLogitDensity) CHECK(decayed.at(i)[k] == set.at(i)[k]);
  }
}

TEST_CASE("densify: the decay's floor raises every density under it and leaves the rest decayed") {
  DensifyConfig config;
  config.decayFloor = 1e-6f;
  GaussianSet set;
  const double densities[] = {1e-12, 1.005e-6, 1e-5, 0.3, 0.999};
  for (double d : densities) addGaussian(set, glm::vec3(0), glm::vec3(0.01f), float(d));
  GaussianSet decayed = set;
  densityDecay(decayed, config);
  for (size_t i = 0; i < set.count(); i++) {
    const double p = sigmoidOf(set.at(i)[f32::kGaussLogitDensity]);
    // relative: doctest's Approx adds its scale (1) to the tolerance, which hides a 1e-6 density
    CHECK(sigmoidOf(decayed.at(i)[f32::kGaussLogitDensity]) / std::max(0.99 * p, 1e-6) == doctest::Approx(1.0).epsilon(1e-5));
  }
  config.decayFloor = 1.0f;
  CHECK_THROWS_AS(densityDecay(set, config), Error);
}

TEST_CASE("densify: bad input is one clear error") {
  GaussianSet set;
  addGaussian(set, glm::vec3(0), glm::vec3(0.01f), 0.5f);
  std::mt19937 rng(1);
  std::vector<uint32_t> rowMap;
  DensifyConfig config;
  CHECK_THROWS_AS(densify(set, std::vector<float>(3, 0.0f), config, 600, rng, rowMap), Error);
  config.sceneExtent = 0;
  CHECK_THROWS_AS(densify(set, std::vector<float>(2, 0.0f), config, 600, rng, rowMap), Error);
  config = DensifyConfig{};
  config.splitScaleDivisor = 1.0f;
  CHECK_THROWS_AS(densify(set, std::vector<float>(2, 0.0f), config, 600, rng, rowMap), Error);
  config = DensifyConfig{};
  config.densifyInterval = 0;
  CHECK_THROWS_AS(densityDecay(set, config), Error);
}

namespace {

// A set for the device comparison: sigmas either side of the clone limit and the large-prune
// limit, densities either side of the prune floor, statistics either side of the threshold
// (a few tied), and Adam moments and statistic sums to carry.
struct DensifyCase {
  GaussianSet set;
  std::vector<float> stats;
  TableAdam adam;
};
DensifyCase randomDensifyCase(std::mt19937& rng, size_t n) {
  DensifyCase c;
  RandomGaussianOptions o;
  o.sigmaMin = 0.002f, o.sigmaMax = 0.15f, o.densityMin = 0.001f;
  c.set = randomGaussians(rng, n, o);
  for (size_t i = 0; i < n; i++)  // a third clone-sized, a few past the large-prune limit
    if (i % 3 == 0 || i % 53 == 7)
      for (int a = 0; a < 3; a++) c.set.at(i)[f32::kGaussLogScale + a] = std::log(i % 3 == 0 ? 0.005f : 0.2f);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (size_t i = 0; i < n; i++) {
    float rays = float(1 + int(20 * U(rng)));
    float mean = U(rng) < 0.3f ? 3e-4f + 1e-3f * U(rng) : 2e-4f * U(rng);
    if (i % 97 == 5) mean = 9e-4f;  // ties in the statistic
    c.stats.insert(c.stats.end(), {mean * rays, rays});
  }
  c.adam = createGaussianAdam(1.0, 1, n);
  for (float& x : c.adam.m) x = U(rng) - 0.5f;
  for (float& x : c.adam.v) x = U(rng);
  return c;
}

}  // namespace

// The device's densification (engine/gaussian/densify_device.h) against the host's, row by row:
// the same rows in the same order, split children to float precision (the device draws them in
// float, the host in double), the Adam moments remapped as remapTableAdamRows does, the
// statistic sums zeroed after a clone/split and kept by a prune alone.
GPU_TEST_CASE("densify on the device: the host's rows, moments and sums, in the host's order") {
  DeviceDensifyPipelines pipelines = createDeviceDensifyPipelines(ctx);
  struct Setting {
    const char* what;
    uint32_t step, maxGaussians;
  };
  for (Setting setting : {Setting{"prune alone", 3100, 1000000}, Setting{"clone, split and prune", 3000, 1000000},
                          Setting{"clone and split capped", 600, 2300}, Setting{"at the cap", 600, 1000}}) {
    DensifyConfig config;
    config.densifyInterval = 300, config.pruneInterval = 100;
    config.maxGaussians = setting.maxGaussians;
    config.pruneLargeFromStep = 3000;
    const uint32_t seed = rng();
    DensifyCase c = randomDensifyCase(rng, 2000);
    INFO(setting.what);

    GaussianSet host = c.set;
    TableAdam hostAdam = c.adam;
    std::vector<uint32_t> rowMap;
    std::mt19937 hostRng(seed), deviceRng(seed);
    DensifyStats want = densify(host, c.stats, config, setting.step, hostRng, rowMap);
    remapTableAdamRows(hostAdam, rowMap);
    const bool keepStats = !densifyDue(config, setting.step);
    std::vector<float> hostSums(rowMap.size() * 2, 0.0f);
    for (size_t i = 0; i < rowMap.size() && keepStats; i++)
      if (rowMap[i] != kNewRow) hostSums[2 * i] = c.stats[2 * rowMap[i]], hostSums[2 * i + 1] = c.stats[2 * rowMap[i] + 1];

    DeviceGaussians dev = uploadGaussians(ctx, c.set);
    GaussianDeviceOptimiser o = createGaussianDeviceOptimiser(ctx, dev.count, kGaussianFloats);
    uploadGaussianOptimiser(ctx, o, c.adam, c.stats);
    DensifyStats got = densifyOnDevice(ctx, pipelines, dev, o, config, setting.step, deviceRng);
    CHECK(hostRng() == deviceRng());  // the same draws taken from the run's generator
    CHECK(got.before == want.before);
    CHECK(got.after == want.after);
    CHECK(got.cloned == want.cloned);
    CHECK(got.split == want.split);
    CHECK(got.prunedLowDensity == want.prunedLowDensity);
    CHECK(got.prunedLarge == want.prunedLarge);
    CHECK(got.cappedOut == want.cappedOut);
    REQUIRE(dev.count == host.count());
    REQUIRE(o.rows == host.count());
    if (std::string(setting.what) == "prune alone") CHECK(want.cloned + want.split == 0);
    else if (std::string(setting.what) == "at the cap") CHECK(want.cappedOut > 0);
    else CHECK_MESSAGE((want.cloned > 0 && want.split > 0), "cloned " << want.cloned << ", split " << want.split << ", capped " << want.cappedOut);
    CHECK(want.prunedLowDensity > 0);
    if (setting.step >= config.pruneLargeFromStep) CHECK(want.prunedLarge > 0);

    GaussianSet gotSet = downloadGaussians(ctx, dev);
    TableAdam gotAdam = hostAdam;
    std::vector<float> gotSums;
    downloadGaussianOptimiser(ctx, o, gotAdam, gotSums);
    size_t rowsDiffer = 0, childrenOff = 0;
    double worstChild = 0;
    for (size_t i = 0; i < host.count(); i++) {
      const bool child = i >= want.after - 2 * size_t(want.split);
      for (uint32_t k = 0; k < kGaussianFloats; k++) {
        const float a = gotSet.at(i)[k], b = host.at(i)[k];
        if (!child) rowsDiffer += a != b;
        else worstChild = std::max(worstChild, double(std::abs(a - b)) / (1.0 + std::abs(b)));
      }
    }
    childrenOff += worstChild > 2e-6;
    CHECK(rowsDiffer == 0);
    INFO("worst split child's difference " << worstChild);
    CHECK(childrenOff == 0);
    CHECK(gotAdam.m == hostAdam.m);
    CHECK(gotAdam.v == hostAdam.v);
    CHECK(gotSums == hostSums);
  }
}

// Equal statistics at the cap: the host takes the lower rows first, and so must the device's
// sort (stable, so its order is the rows' among equal keys).
GPU_TEST_CASE("densify on the device: equal statistics at the cap go to the lower rows, as on the host") {
  DeviceDensifyPipelines pipelines = createDeviceDensifyPipelines(ctx);
  DensifyConfig config;
  GaussianSet set;
  std::vector<float> stats;
  for (int i = 0; i < 600; i++) {
    addGaussian(set, glm::vec3(0.001f * float(i), 0, 0), glm::vec3(0.01f), 0.5f);  // clone-sized
    stats.insert(stats.end(), {i % 2 ? 2e-3f : 1e-3f, 1.0f});                    // two tied groups
  }
  config.maxGaussians = 600 + 200;  // room for 200 of the 300 odd rows (the larger statistic), none of the even
  TableAdam adam = createGaussianAdam(1.0, 1, set.count());
  GaussianSet host = set;
  std::vector<uint32_t> rowMap;
  std::mt19937 hostRng(1), deviceRng(1);
  DensifyStats want = densify(host, stats, config, 600, hostRng, rowMap);
  REQUIRE(want.cloned == 200);
  CHECK(rowMap[600] == kNewRow);
  DeviceGaussians dev = uploadGaussians(ctx, set);
  GaussianDeviceOptimiser o = createGaussianDeviceOptimiser(ctx, dev.count, kGaussianFloats);
  uploadGaussianOptimiser(ctx, o, adam, stats);
  DensifyStats got = densifyOnDevice(ctx, pipelines, dev, o, config, 600, deviceRng);
  REQUIRE(got.cloned == 200);
  GaussianSet gotSet = downloadGaussians(ctx, dev);
  CHECK(gotSet.params == host.params);  // the clones of rows 1, 3, ..., 399, in row order
  CHECK(host.at(600)[0] == set.at(1)[0]);
  CHECK(host.at(799)[0] == set.at(399)[0]);
}
