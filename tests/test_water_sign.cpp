// Waves learned upside down (docs/experiments/2026-11-28-upside-down-water.md): a height
// field's mirror image about the water height, the views' plane-sweep agreement through a
// water against through its mirror, and --water-sign-check at a restart, on the tiny
// NeRFrac-like preset with its height field fitted directly to the true waves or to their mirror.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "engine/base/error.h"
#include "engine/dataset/ground_truth.h"
#include "engine/height/analytic_height.h"
#include "engine/model/model.h"
#include "engine/train/train_session.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

// Points on an n x n grid over the surface's domain, as float2.
std::vector<float> domainGrid(const TrainConfig& c, int n) {
  std::vector<float> xy;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      xy.push_back(float(c.domain.xMin + (c.domain.xMax - c.domain.xMin) * (i + 0.5) / n));
      xy.push_back(float(c.domain.yMin + (c.domain.yMax - c.domain.yMin) * (j + 0.5) / n));
    }
  return xy;
}

// The session's height field fitted to `target` on a 48 x 48 grid over the domain by Adam on
// the mean squared error (a known surface without training through the views), and the
// surface lifted from it.
void fitHeightField(Context& ctx, TrainSession& s, const std::function<double(double, double)>& target) {
  HeightField& hf = *s.model.height;
  const std::vector<float> xy = domainGrid(s.model.config, 48);
  const uint32_t n = uint32_t(xy.size() / 2);
  std::vector<float> targets(n);
  for (uint32_t k = 0; k < n; k++) targets[k] = float(target(xy[2 * k], xy[2 * k + 1]));
  Buffer points = createBufferFrom(ctx, xy);
  Buffer heights = createBuffer(ctx, n * 4), dLoss = createBuffer(ctx, n * 4), grad = createBuffer(ctx, hf.parameterCount * 4);
  fillBuffer(ctx, grad, 0);
  AdamGroup adam = createAdamGroup(ctx, "fit", LearningRateSchedule{3e-3, 3e-3, 1}, 1, uint32_t(hf.parameterCount));
  AdamPipelines pipelines = createAdamPipelines(ctx);
  for (int it = 0; it < 300; it++) {
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdEvaluateHeights(cb, hf, points, n, heights); });
    std::vector<float> h = downloadVector<float>(ctx, heights, n), d(n);
    for (uint32_t k = 0; k < n; k++) d[k] = 2 * (h[k] - targets[k]) / float(n);
    upload(ctx, dLoss, d.data(), n * 4);
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cmdAccumulateHeightGradients(cb, hf, points, dLoss, n, grad);
      cmdBarrier(cb);
      cmdAdamStep(cb, pipelines, adam, hf.weights, grad, 0, true);
    });
  }
  liftSurface(s.model);
}

// Pearson correlation of the learned heights with `truth` on a 97 x 97 grid over the domain
// (sampleWaterHeights: between the fit's points too).
double correlationWith(TrainSession& s, const std::function<double(double, double)>& truth) {
  const uint32_t n = 97;
  const std::vector<double> h = sampleWaterHeights(s.model, n, n);
  const Rect& r = s.model.config.domain;
  std::vector<double> t(h.size());
  for (uint32_t j = 0; j < n; j++)
    for (uint32_t i = 0; i < n; i++) t[j * n + i] = truth(r.xMin + (r.xMax - r.xMin) * i / (n - 1), r.yMin + (r.yMax - r.yMin) * j / (n - 1));
  double mh = 0, mt = 0;
  for (size_t k = 0; k < h.size(); k++) {
    mh += h[k] / double(h.size());
    mt += t[k] / double(h.size());
  }
  double ht = 0, hh = 0, tt = 0;
  for (size_t k = 0; k < h.size(); k++) {
    ht += (h[k] - mh) * (t[k] - mt);
    hh += (h[k] - mh) * (h[k] - mh);
    tt += (t[k] - mt) * (t[k] - mt);
  }
  return ht / std::sqrt(hh * tt);
}

}  // namespace

// One backend: the check decides on the sweeps' costs, and the sweep through the water is checked on
// both backends (test_plane_sweep.cpp); this case takes about a minute.
GPU_TEST_CASE("water sign: a height field's mirror image, and --water-sign-check keeps the mirror of waves fitted upside down" *
              doctest::test_suite("one-backend")) {
  // The strong-wave variant (the long test's): through the preset's own 64-px views at IOR 1.1
  // the sweep reads the true waves and their mirror alike (0.98x).
  std::string data = test::tinyDataset("nerfrac-primary-sine", "--width 192");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 4, 300, 16, 1, d);
  c.mlpCoarseOctaves = c.mlpOctaves;  // every octave open: the fit holds the waves
  c.schedule.gaussianRestarts = {1};
  c.schedule.surfaceFreeze = 0;
  const AnalyticWaves waves = loadGroundTruthWaves(d);
  const double level = c.waterHeight;
  auto truth = [&](double x, double y) { return analyticHeightRef(waves, x, y); };
  auto upsideDown = [&](double x, double y) { return 2 * level - analyticHeightRef(waves, x, y); };

  SUBCASE("the mirror image is 2 level - H, and mirroring twice gives the weights back") {
    auto s = createTrainSession(ctx, c, d);
    s->model.height->config.initialHeight = float(level + 0.01);  // as an anchored water's may be
    const std::vector<double> before = sampleWaterHeights(s->model, 24, 24);
    const std::vector<float> weights = downloadWeights(ctx, *s->model.height);
    mirrorHeightField(ctx, *s->model.height, level);
    const std::vector<double> after = sampleWaterHeights(s->model, 24, 24);
    for (size_t k = 0; k < before.size(); k++) CHECK(after[k] == doctest::Approx(2 * level - before[k]).epsilon(1e-6).scale(1e-6));
    mirrorHeightField(ctx, *s->model.height, level);
    CHECK(downloadWeights(ctx, *s->model.height) == weights);
  }

  SUBCASE("scaling the relief: H' = level + S (H - level), and S = 0 flat at the level") {
    auto s = createTrainSession(ctx, c, d);
    s->model.height->config.initialHeight = float(level + 0.01);
    const std::vector<double> before = sampleWaterHeights(s->model, 24, 24);
    const std::vector<float> weights = downloadWeights(ctx, *s->model.height);
    const float initialHeight = s->model.height->config.initialHeight;
    for (double scale : {0.5, 2.0, 0.0}) {
      uploadWeights(ctx, *s->model.height, weights);
      s->model.height->config.initialHeight = initialHeight;
      const double about = level + 0.05;  // a level of its own: the preset's water is at z = 0
      scaleHeightField(ctx, *s->model.height, about, scale);
      const std::vector<double> after = sampleWaterHeights(s->model, 24, 24);
      CAPTURE(scale);
      for (size_t k = 0; k < before.size(); k++)
        CHECK(after[k] == doctest::Approx(about + scale * (before[k] - about)).epsilon(1e-6).scale(1e-6));
    }
  }

  SUBCASE("--water-scale-search: the scale the views agree best through is kept when clearly better, else the water as learned") {
    c.waterScaleSearch = true;
    c.surfaceBatch = 1000;  // no surface step at step 1: what the restart finds is what was fitted
    // Waves three times too high and shifted by a quarter period: wrong water the sweep sees.
    auto wrong = [&](double x, double y) {
      AnalyticWaves w = waves;
      for (auto& k : w.waves) k[0] *= 3, k[3] += 1.5707963f;
      return analyticHeightRef(w, x, y);
    };
    auto s = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *s, wrong);
    const std::vector<double> fitted = sampleWaterHeights(s->model, 24, 24);
    CHECK(trainStep(*s).restarted);
    REQUIRE(s->log.scaleSearches.size() == 1);
    const WaterScaleSearch& w = s->log.scaleSearches[0];
    REQUIRE(w.ratios.size() == std::size(kWaterScales));
    CHECK(w.ratios[2] == 1.0);  // the learned water against itself
    MESSAGE("wrong waves, sweep cost at 0, 0.5, 1, 1.5, 2x the learned height: " << w.ratios[0] << ", " << w.ratios[1] << ", 1, "
                                                                                << w.ratios[3] << ", " << w.ratios[4] << "; kept " << w.chosen << "x");
    const size_t best = size_t(std::min_element(w.ratios.begin(), w.ratios.end()) - w.ratios.begin());
    REQUIRE(w.ratios[best] < kWaterScaleBetter);  // this water is clearly beaten
    CHECK(w.chosen == kWaterScales[best]);
    CHECK(w.chosen < 1.0);
    // the kept relief is the fitted one scaled (up to the anchor's uniform shift)
    const std::vector<double> kept = sampleWaterHeights(s->model, 24, 24);
    double fittedMean = 0, keptMean = 0;
    for (size_t k = 0; k < kept.size(); k++) fittedMean += fitted[k] / double(kept.size()), keptMean += kept[k] / double(kept.size());
    for (size_t k = 0; k < kept.size(); k++)
      CHECK(kept[k] - keptMean == doctest::Approx(w.chosen * (fitted[k] - fittedMean)).scale(1e-4));

    // A nearly flat water: every scale reads about alike, none clearly better, the weights kept.
    c.mlpInitRange = 1e-7;
    auto flat = createTrainSession(ctx, c, d);
    const std::vector<float> weights = downloadWeights(ctx, *flat->model.height);
    CHECK(trainStep(*flat).restarted);
    REQUIRE(flat->log.scaleSearches.size() == 1);
    for (double r : flat->log.scaleSearches[0].ratios) CHECK(r == doctest::Approx(1.0).epsilon(0.03));
    CHECK(flat->log.scaleSearches[0].chosen == 1.0);
    CHECK(downloadWeights(ctx, *flat->model.height) == weights);
  }

  SUBCASE("the views agree more through the waves than through their mirror; at a restart the check keeps them, and turns "
          "waves fitted upside down the right way up") {
    c.waterSignCheck = true;
    auto s = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *s, truth);
    REQUIRE(correlationWith(*s, truth) > 0.8);
    const std::vector<float> weights = downloadWeights(ctx, *s->model.height);
    const float initialHeight = s->model.height->config.initialHeight;
    const std::vector<float> grid = downloadVector<float>(ctx, s->model.surface->gridHeights, s->model.surface->gridPointCount);
    const SweepAgreement a = agreementOfMirror(*s);
    CHECK(a.cells > 1000);
    CHECK(a.cost > a.reference);
    CHECK(downloadWeights(ctx, *s->model.height) == weights);  // the water as it was
    CHECK(s->model.height->config.initialHeight == initialHeight);
    CHECK(downloadVector<float>(ctx, s->model.surface->gridHeights, s->model.surface->gridPointCount) == grid);
    CHECK(trainStep(*s).restarted);  // step 1
    REQUIRE(s->log.signChecks.size() == 1);
    CHECK(s->log.signChecks[0].step == 1);
    CHECK_FALSE(s->log.signChecks[0].mirrored);
    // the check also records the learned water against flat water (agreementWithFlatWater, tested
    // in test_plane_sweep.cpp), but not which is better: this fitted field (300 Adam steps on a
    // 48 x 48 grid, correlation > 0.8 with the waves) reads 3.6x flat water's cost
    const SweepAgreement& flat = s->log.signChecks[0].flat;
    MESSAGE("the fitted waves' sweep cost: " << flat.cost / flat.reference << "x flat water's");
    CHECK(flat.cells > 1000);
    CHECK(flat.cost > 0);
    CHECK(flat.reference > 0);

    auto inverted = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *inverted, upsideDown);
    REQUIRE(correlationWith(*inverted, truth) < -0.8);
    CHECK(trainStep(*inverted).restarted);
    REQUIRE(inverted->log.signChecks.size() == 1);
    const SweepAgreement& flip = inverted->log.signChecks[0].agreement;
    MESSAGE("the mirror's sweep cost: " << a.cost / a.reference << "x the fitted waves', " << flip.cost / flip.reference
                                        << "x the waves fitted upside down");
    CHECK(inverted->log.signChecks[0].mirrored);
    CHECK(correlationWith(*inverted, truth) > 0.8);
    trainStep(*inverted);  // it trains on
  }

  SUBCASE("--surface-gate: at a restart, water the views agree less through than flat water starts again from flat") {
    // Waves three times too high and shifted by a quarter period: wrong water the sweep sees.
    auto wrong = [&](double x, double y) {
      AnalyticWaves w = waves;
      for (auto& k : w.waves) k[0] *= 3, k[3] += 1.5707963f;
      return analyticHeightRef(w, x, y);
    };
    c.surfaceGate = 1.0;
    c.surfaceBatch = 1000;  // no surface step at step 1: what the restart finds is what was fitted
    auto s = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *s, wrong);
    CHECK(trainStep(*s).restarted);
    REQUIRE(s->log.gateChecks.size() == 1);
    const SweepAgreement& a = s->log.gateChecks[0].agreement;
    MESSAGE("the wrong waves' sweep cost: " << a.cost / a.reference << "x flat water's");
    CHECK(a.cost > a.reference);
    CHECK(s->log.gateChecks[0].reset);
    CHECK(downloadWeights(ctx, *s->model.height) == initialHeightWeights(s->model.height->config, heightFieldSeed(c)));
    CHECK(s->model.height->config.initialHeight == float(level));
    const std::vector<double> start = sampleWaterHeights(createTrainSession(ctx, c, d)->model, 24, 24), now = sampleWaterHeights(s->model, 24, 24);
    for (size_t k = 0; k < start.size(); k++) CHECK(now[k] == doctest::Approx(start[k]).epsilon(1e-6).scale(1e-6));  // the flat start's heights
    trainStep(*s);  // it trains on

    c.surfaceGate = 1e9;  // a gate that passes everything keeps the wrong water, and records it
    auto kept = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *kept, wrong);
    const std::vector<float> weights = downloadWeights(ctx, *kept->model.height);
    CHECK(trainStep(*kept).restarted);
    REQUIRE(kept->log.gateChecks.size() == 1);
    CHECK_FALSE(kept->log.gateChecks[0].reset);
    CHECK(downloadWeights(ctx, *kept->model.height) == weights);

    CHECK(trainConfigFromJson(trainConfigToJson(c), "test").surfaceGate == 1e9);
    c.schedule.gaussianRestarts = {};
    CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--surface-gate"), Error);
  }

  SUBCASE("--sweep-watch: water the views agree on less than on flat water goes back to the best water of the checks, its "
          "learning rate halved") {
    // Waves three times too high and shifted by a quarter period: wrong water the sweep sees.
    auto wrong = [&](double x, double y) {
      AnalyticWaves w = waves;
      for (auto& k : w.waves) k[0] *= 3, k[3] += 1.5707963f;
      return analyticHeightRef(w, x, y);
    };
    c.schedule.gaussianRestarts = {};
    // Two octaves: the waves fitted with every octave open read 3.1-3.5x flat water's sweep cost
    // (the fit's wiggles between its points bend the rays), with two 0.55x (the true waves: 0.44x).
    c.mlpCoarseOctaves = 2;
    c.sweepWatch = 1;       // a check at every step
    c.surfaceBatch = 1000;  // and no surface step: each check finds what was fitted
    const double rate = c.surfaceLearningRate;

    // No water better than flat yet: the wrong waves go back to flat water at the water height.
    auto s = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *s, wrong);
    trainStep(*s);
    REQUIRE(s->log.watchChecks.size() == 1);
    const SweepWatchCheck& first = s->log.watchChecks[0];
    const SweepAgreement& a = first.agreement;
    MESSAGE("the wrong waves' sweep cost: " << a.cost / a.reference << "x flat water's");
    CHECK(a.cost > a.reference);
    CHECK(first.rolledBack);
    CHECK_FALSE(first.best);
    CHECK(first.learningRateScale == 0.5);
    CHECK(s->water.heightAdam.lr.initial == doctest::Approx(0.5 * rate));
    for (double h : sampleWaterHeights(s->model, 24, 24)) CHECK(h == doctest::Approx(level).scale(1e-6));

    // The true waves are the best so far and kept; wrong waves after them go back to them.
    auto t = createTrainSession(ctx, c, d);
    fitHeightField(ctx, *t, truth);
    trainStep(*t);
    REQUIRE(t->log.watchChecks.size() == 1);
    const SweepAgreement& b = t->log.watchChecks[0].agreement;
    MESSAGE("the true waves' sweep cost: " << b.cost / b.reference << "x flat water's");
    CHECK(b.cost < b.reference);
    CHECK(t->log.watchChecks[0].best);
    CHECK_FALSE(t->log.watchChecks[0].rolledBack);
    const std::vector<double> trueHeights = sampleWaterHeights(t->model, 24, 24);
    fitHeightField(ctx, *t, wrong);
    trainStep(*t);
    REQUIRE(t->log.watchChecks.size() == 2);
    CHECK(t->log.watchChecks[1].rolledBack);
    CHECK(correlationWith(*t, truth) > 0.8);
    const std::vector<double> back = sampleWaterHeights(t->model, 24, 24);
    double mean = 0, trueMean = 0;  // up to the anchor's uniform shift
    for (size_t k = 0; k < back.size(); k++) mean += back[k] / double(back.size()), trueMean += trueHeights[k] / double(back.size());
    for (size_t k = 0; k < back.size(); k++) CHECK(back[k] - mean == doctest::Approx(trueHeights[k] - trueMean).scale(1e-4));
    trainStep(*t);  // it trains on
    CHECK(t->log.watchChecks.size() == 3);

    // A watch longer than the run still checks the water the run ends with.
    c.sweepWatch = 1000;
    auto u = createTrainSession(ctx, c, d);
    while (u->model.step < c.steps) trainStep(*u);
    REQUIRE(u->log.watchChecks.size() == 1);
    CHECK(u->log.watchChecks[0].step == c.steps);

    CHECK(trainConfigFromJson(trainConfigToJson(c), "test").sweepWatch == 1000);
    c.model = WaterModel::FlatWater;
    CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--sweep-watch"), Error);
  }

  SUBCASE("the option survives config.json and needs a learned water and a restart") {
    c.waterSignCheck = true;
    CHECK(trainConfigFromJson(trainConfigToJson(c), "test").waterSignCheck);
    nlohmann::json old = trainConfigToJson(c);
    old.erase("water_sign_check");
    CHECK_FALSE(trainConfigFromJson(old, "old").waterSignCheck);  // runs from before the option
    c.schedule.gaussianRestarts = {};
    CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--water-sign-check"), Error);
    c.schedule.gaussianRestarts = {1};
    c.model = WaterModel::FlatWater;
    CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--water-sign-check"), Error);
  }
}

TEST_CASE("--sweep-watch's verdict: a new best below the best so far, 1% over flat water's sweep cost let pass, more rolled back") {
  // The ratio is the learned water's sweep cost over flat water's; the best so far starts at 1.
  CHECK(sweepWatchVerdict(0.9, 1.0) == SweepWatchVerdict::Best);
  CHECK(sweepWatchVerdict(0.95, 0.9) == SweepWatchVerdict::Keep);  // worse than the best, better than flat
  CHECK(sweepWatchVerdict(1.005, 1.0) == SweepWatchVerdict::Keep);  // noise: dev 7's flat water read 1.0004-1.0042
  CHECK(sweepWatchVerdict(1.005, 0.9) == SweepWatchVerdict::Keep);
  CHECK(sweepWatchVerdict(1.02, 1.0) == SweepWatchVerdict::RollBack);
  CHECK(sweepWatchVerdict(1.02, 0.9) == SweepWatchVerdict::RollBack);
  CHECK(sweepWatchVerdict(INFINITY, 1.0) == SweepWatchVerdict::RollBack);  // no cell swept
}

TEST_CASE("--restart-gate: a restart is drawn only below X times flat water's sweep cost") {
  SweepAgreement a;
  a.cells = 100, a.reference = 2.0;
  a.cost = 1.9;  // 0.95x flat water's
  CHECK(restartGatePasses(a, 0.99));
  CHECK_FALSE(restartGatePasses(a, 0.95));  // not below
  a.cost = 2.0;
  CHECK_FALSE(restartGatePasses(a, 0.99));  // flat water itself: nothing learned to refit to
  a.cells = 0;
  CHECK(restartGatePasses(a, 0.99));  // nothing swept: restart, as without the gate
}

// End to end: one restart step, a gate no water can pass (the sweep costs' ratio is positive)
// and one every water passes; the run reports each check and restarts only past the second.
GPU_TEST_CASE("--restart-gate: a run keeps its Gaussians where the gate is shut and draws them afresh where it is open") {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string options = " --steps 240 --surface-freeze 40 --restart-gaussians 160 --progress-every 80 --checkpoint-every 0";
  nlohmann::json shut = test::trainAndReadMetrics(data, dir / "shut", options + " --restart-gate 1e-9");
  nlohmann::json open = test::trainAndReadMetrics(data, dir / "open", options + " --restart-gate 1e9");
  REQUIRE(shut.contains("restart_gate_checks"));
  REQUIRE(open.contains("restart_gate_checks"));
  CHECK(shut["restart_gate_checks"].size() == 1);
  CHECK(shut["restart_gate_checks"][0]["step"] == 160);
  CHECK(shut["restart_gate_checks"][0]["restarted"] == false);
  CHECK(open["restart_gate_checks"][0]["restarted"] == true);
  CHECK(shut["restart_gate_checks"][0]["ratio"].get<double>() > 0);
  // It needs a learned water and a restart to gate.
  test::checkOneError(test::runCli("train " + data + " -o " + (dir / "bad") + options + " --restart-gate 0.99 --restart-gaussians 0"),
                      "--restart-gate");
  test::checkOneError(test::runCli("train " + data + " -o " + (dir / "bad") + options + " --restart-gate 0.99 --flat-water"),
                      "--restart-gate");
}
