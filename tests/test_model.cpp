// The model apart from training (engine/model/open_model.h): what `refrax render`, `refrax eval`
// and the viewer load from a run is what the training session holds at that checkpoint — the
// same Gaussians, the same water (weights, encoding window, anchored mean height or plane
// height), the same renders — without building a training session.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/model/open_model.h"
#include "engine/model/render_model.h"
#include "engine/io/json_io.h"
#include "engine/train/checkpoint.h"
#include "engine/train/train_run.h"
#include "engine/vk/vk_profile.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

// Heights (m) that differ by float rounding only.
constexpr double kHeightRounding = 1e-7;

double largestDifference(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  double most = 0;
  for (size_t i = 0; i < a.size(); i++) most = std::max(most, double(std::abs(a[i] - b[i])));
  return most;
}

// A session of `steps` steps on the tiny sine preset (its configuration changed by `change`),
// saved as a run (config.json and a checkpoint), opened as a model, compared with the live
// session: not reloaded, so the model's loading is checked against where training left it.
template <class Change>
void checkModelMatchesSession(Context& ctx, int steps, Change change) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, steps, 200, 16, test::freshSeed(), d);
  change(c);
  resolveSchedule(c);
  auto session = createTrainSession(ctx, c, d);
  while (session->model.step < steps) trainStep(*session);
  const std::string run = dir / "run";
  std::filesystem::create_directories(run);
  writeJson(run + "/config.json", trainConfigToJson(session->model.config));
  saveCheckpoint(*session, run);

  const Dataset dataset = loadRunDataset(readRunConfig(run));
  auto model = openModel(ctx, run, dataset);
  CHECK(model->step == session->model.step);
  CHECK(model->trainingSeconds == session->model.trainingSeconds);
  CHECK(model->gaussians.params == session->model.gaussians.params);
  CHECK(model->planeHeight == session->model.planeHeight);
  CHECK(bool(model->surface) == bool(session->model.surface));
  if (session->model.height) {
    REQUIRE(model->height);
    CHECK(model->height->config.encodingWindow == session->model.height->config.encodingWindow);
    // The anchored constant: training reaches it by one shift per surface step, the load by
    // one shift from the base, so the two agree to float rounding (measured up to 1e-9 m; the
    // anchor left out on load is 1e-4 to 1e-2 m off).
    CHECK(std::abs(model->height->config.initialHeight - session->model.height->config.initialHeight) <= kHeightRounding);
  }
  const std::vector<double> a = sampleWaterHeights(*model, 9, 9), b = sampleWaterHeights(session->model, 9, 9);
  REQUIRE(a.size() == b.size());
  for (size_t k = 0; k < a.size(); k++) CHECK(std::abs(a[k] - b[k]) <= kHeightRounding);
  const Camera& camera = dataset.split("test")[0].camera;
  for (WaterView water : {WaterView::Keep, WaterView::Remove}) {
    RenderedView fromModel = renderView(*model, camera, water), fromSession = renderView(session->model, camera, water);
    CHECK(largestDifference(fromModel.image.pixels, fromSession.image.pixels) <= 1e-5);  // a wrong water: 0.02
    CHECK(fromModel.missed == fromSession.missed);
    // An image alone (an evaluation's views that only compare images) is one submission where
    // the water's trace is one, the same image and misses as the stages' path (issue 48).
    GpuProfiler counter;
    attachProfiler(ctx, counter);
    RenderedView alone = renderView(*model, camera, water, SwapSurface{}, kImageOnly);
    detachProfiler(ctx);
    CHECK(alone.image.pixels == fromModel.image.pixels);
    CHECK(alone.missed == fromModel.missed);
    const bool oneTrace = water == WaterView::Remove || !model->surface || traceIsOneSubmission(*model->surface, currentHeightSource(*model), uint32_t(camera.width * camera.height));
    if (oneTrace) CHECK(counter.submits == 1);
  }
  // A render larger than the dataset's images grows the model's ray buffers (and its surface).
  Camera large = camera;
  large.width *= 2;
  large.height *= 2;
  large.fx *= 2;
  large.fy *= 2;
  large.cx *= 2;
  large.cy *= 2;
  RenderedView big = renderView(*model, large, WaterView::Keep);
  CHECK(big.image.pixels.size() == size_t(large.width) * large.height * 3);
  CHECK(model->capacity >= uint32_t(large.width * large.height));
}

}  // namespace

GPU_TEST_CASE("model: a run opened as a model holds what its training session holds at that checkpoint, and renders the same") {
  SUBCASE("learned water, its mean height anchored, its octaves opening") {
    checkModelMatchesSession(ctx, 12, [](TrainConfig& c) {
      c.schedule.surfaceFreeze = 4;
      c.anchorMeanHeight = true;
      c.mlpCoarseOctaves = 2;
      c.schedule.octavesOpenUntil = 30;
    });
  }
  SUBCASE("flat water") {
    checkModelMatchesSession(ctx, 8, [](TrainConfig& c) {
      c.schedule.surfaceFreeze = 2;
      c.model = WaterModel::FlatWater;
    });
  }
  SUBCASE("no refraction") { checkModelMatchesSession(ctx, 4, [](TrainConfig& c) { c.model = WaterModel::NoRefraction; }); }
}

GPU_TEST_CASE("model: opening a run without a checkpoint or with a checkpoint of another model is one clear error" *
              doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "run") + " --steps 2 --gaussians 100 --patch 16 --flat-water");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const std::string run = dir / "run";
  TrainConfig config = readRunConfig(run);
  const Dataset dataset = loadRunDataset(config);
  auto model = openModel(ctx, run, dataset);
  // The same run's checkpoint read as the learned-water model's: refused, the model untouched.
  Model other;
  config.model = WaterModel::Refraction;
  initModel(other, ctx, config, dataset);
  CHECK_THROWS_WITH_AS(loadModelCheckpoint(other, latestCheckpoint(run), dataset), doctest::Contains("different water model"), Error);
  CHECK(other.step == 0);
  std::filesystem::remove_all(std::filesystem::path(run) / "checkpoints");
  CHECK_THROWS_WITH_AS(openModel(ctx, run, dataset), doctest::Contains("has no checkpoint yet"), Error);
}
