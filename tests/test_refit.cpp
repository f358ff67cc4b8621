// --refit N (issue 45): after the run's steps, N more steps of Gaussians drawn afresh under the
// water as learned, held fixed, their schedule counted again from the refit's start. Fresh
// Gaussians under the learned water of evaluation scene 1008 ended 1.3 dB over the run's own;
// a refit whose water still moved, whose Gaussians kept their history, or whose schedule ran on
// from the run's step would not be that.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/height/height_field.h"
#include "engine/io/json_io.h"
#include "engine/model/model.h"
#include "engine/vk/vk_buffer.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// Six steps, then a refit of six: the water learns fast from step 1, one density reset after
// step 4 (no decay, so a reset is the only way every density falls to its value).
TrainConfig refitConfig(Dataset& d, uint64_t seed) {
  TrainConfig c = test::sessionConfig(test::tinyDataset("nerfrac-primary-sine"), 6, 300, 16, seed, d);
  c.schedule.refitSteps = 6;
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 1e-2;
  c.schedule.densityDecayInterval = 0;
  c.schedule.densityResetInterval = 4;
  c.schedule.densityResetUntil = 5;
  return c;
}

bool everyDensityReset(TrainSession& s) {
  pullGaussians(s);
  const float limit = float(std::log(s.model.config.densityResetValue / (1.0 - s.model.config.densityResetValue)));
  for (size_t i = 0; i < s.model.gaussians.count(); i++)
    if (s.model.gaussians.at(i)[f32::kGaussLogitDensity] > limit + 1e-6f) return false;
  return true;
}

}  // namespace

TEST_CASE("train: --refit counts the Gaussians' schedule from its start, and is validated") {
  Dataset d;
  TrainConfig c = test::sessionConfig(test::tinyDataset("nerfrac-primary-sine"), 100, 300, 16, 1, d);
  c.schedule.shDegreeInterval = 10;
  c.maxShDegree = 3;
  CHECK(totalSteps(c) == 100);
  CHECK(shDegreeAt(c, 101) == 3);
  c.schedule.refitSteps = 90;
  CHECK(totalSteps(c) == 190);
  CHECK(gaussianScheduleStep(c, 100) == 100);
  CHECK(gaussianScheduleStep(c, 101) == 1);
  CHECK(refitStartsAt(c, 101));
  CHECK_FALSE(refitStartsAt(c, 100));
  CHECK(shDegreeAt(c, 100) == 3);
  CHECK(shDegreeAt(c, 101) == 0);  // the refit's first step sees degree 0 again
  CHECK(shDegreeAt(c, 121) == 2);
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").schedule.refitSteps == 90);
  nlohmann::json older = trainConfigToJson(c);
  older["schedule"].erase("refit_steps");  // a run written before the option has no refit
  CHECK(trainConfigFromJson(older, "test").schedule.refitSteps == 0);
  // The refit must outlast the Gaussians' schedule sized for --steps (densification until step
  // 80 of 100 here), or the run would end on a densification or a density reset.
  c.densify = true;
  c.schedule.refitSteps = 50;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("at least 81 steps"), Error);
  c.schedule.refitSteps = 81;
  CHECK_NOTHROW(validateTrainConfig(c));
  c.gaussiansFixed = true;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--refit"), Error);
  c.gaussiansFixed = false;
  c.schedule.refitSteps = -1;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--refit"), Error);
}

GPU_TEST_CASE("train: --refit draws fresh Gaussians after --steps, holds the water, and runs their schedule again" *
              doctest::test_suite("one-backend")) {
  Dataset d;
  const TrainConfig c = refitConfig(d, rng());
  auto s = createTrainSession(ctx, c, d);
  std::set<int> resets;
  std::vector<float> weightsAtFirstStep;
  while (s->model.step < c.steps) {
    CHECK_FALSE(trainStep(*s).refitStarted);
    if (s->model.step == 1) weightsAtFirstStep = downloadVector<float>(ctx, s->model.height->weights, s->model.height->parameterCount);
    if (everyDensityReset(*s)) resets.insert(s->model.step);
  }
  REQUIRE(resets == std::set<int>{4});
  pullGaussians(*s);
  const GaussianSet trained = s->model.gaussians;
  const std::vector<float> learned = downloadVector<float>(ctx, s->model.height->weights, s->model.height->parameterCount);
  double moved = 0;
  for (size_t i = 0; i < learned.size(); i++) moved = std::max(moved, double(std::abs(learned[i] - weightsAtFirstStep[i])));
  CHECK(moved > 1e-4);  // the water learned in the run's steps

  const StepResult first = trainStep(*s);
  CHECK(first.refitStarted);
  CHECK(s->model.step == c.steps + 1);
  // Fresh: new positions, and the Gaussians' Adam one step old (it was six).
  pullGaussians(*s);
  double shifted = 0;
  for (size_t i = 0; i < std::min(trained.count(), s->model.gaussians.count()); i++)
    shifted += std::abs(s->model.gaussians.at(i)[f32::kGaussMean] - trained.at(i)[f32::kGaussMean]);
  CHECK(shifted / 300.0 > 0.01);
  for (const auto& g : s->state.gaussianAdam.groups) CHECK(g.step == 1);
  // The schedule again from its start: the reset after the refit's fourth step, not after the
  // run's; and the water held through every refit step.
  std::set<int> refitResets;
  while (s->model.step < totalSteps(c)) {
    CHECK_FALSE(trainStep(*s).refitStarted);
    if (everyDensityReset(*s)) refitResets.insert(s->model.step - c.steps);
  }
  CHECK(refitResets == std::set<int>{4});
  CHECK(downloadVector<float>(ctx, s->model.height->weights, s->model.height->parameterCount) == learned);
}

TEST_CASE("train: refrax train --refit evaluates the run's own Gaussians at --steps, says the refit, and refuses a bad value" *
          doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string options = " --steps 20 --refit 20 --eval-every 20 --gaussians 300 --patch 16 --progress-every 10 --checkpoint-every 0";
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "run") + options);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(r.output.find("20 steps and a refit of 20") != std::string::npos);
  CHECK(r.output.find("step 21: the refit: 20 steps of Gaussians drawn afresh") != std::string::npos);
  CHECK(r.output.find("step     40/40") != std::string::npos);
  const nlohmann::json evaluations = readJson(dir / "run/evaluations.json");
  REQUIRE(evaluations.size() == 1);
  CHECK(evaluations[0]["step"] == 20);
  const nlohmann::json metrics = readJson(dir / "run/metrics.json");
  CHECK(metrics["step"] == 40);
  // The water held: the evaluation at step 20 and the run's end read the same surface error.
  CHECK(evaluations[0]["surface_rmse"].get<double>() == doctest::Approx(metrics["surface_rmse"].get<double>()).epsilon(1e-6));
  for (const std::string& refused : {std::string(" --steps 4 --refit -3"), std::string(" --steps 20 --refit 10"), std::string(" --time-limit 5 --refit 20")}) {
    test::CliResult bad = test::runCli("train " + data + " -o " + (dir / "bad") + refused + " --gaussians 100");
    INFO(refused);
    test::checkOneError(bad, "--refit");
    CHECK_FALSE(fs::exists(dir / "bad"));
  }
}

}  // namespace refrax
