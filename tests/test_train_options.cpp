// The training options' table (engine/run/train_options.h): the parser, config.json and
// validation come from its rows, so each row is checked once here: a non-default value goes
// from the command line's text into TrainConfig, through config.json and back unchanged, an
// out-of-range value is refused naming the flag, and --help lists every flag.
#include <doctest/doctest.h>

#include <map>

#include "engine/base/error.h"
#include "engine/run/train_options.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

// A valid configuration as resolveSceneConfig leaves one (the resolved values set).
TrainConfig resolvedConfig() {
  TrainConfig c;
  c.dataset = "/data/x";
  c.domain = Rect{-1, -1, 1, 1};
  c.boxMax[2] = 1;
  resolveSchedule(c);
  c.schedule.gaussianRestarts = {100};  // what --water-sign-check needs beside it (before the --steps sample)
  return c;
}

// A value other than the default for every option with a flag, and one out of its range
// (empty: the option takes any value of its type).
const std::map<std::string, std::pair<std::string, std::string>> kSamples = {
    {"no-refraction", {"", ""}}, {"flat-water", {"", ""}}, {"known-water", {"", ""}},
    {"recipe", {"method", "paper"}}, {"steps", {"123", "0"}}, {"seed", {"77", "-1"}}, {"gaussians", {"321", "0"}}, {"init-depth", {"sweep", "deep"}}, {"init-points", {"", ""}},
    {"gaussians-from", {"oracle/point_cloud.ply", ""}}, {"gaussians-fixed", {"", ""}},
    {"max-gaussians", {"2000000", "0"}}, {"initial-density", {"0.25", "1"}}, {"sh-degree", {"1", "4"}},
    {"k-buffer", {"16", "65"}}, {"hit-records", {"8", "1025"}}, {"proxy", {"instanced", "sphere"}},
    {"mlp-width", {"32", "257"}}, {"mlp-layers", {"2", "0"}}, {"mlp-octaves", {"4", "17"}},
    {"mlp-coarse-octaves", {"2", "17"}}, {"mlp-init-range", {"0.01", "-0.1"}}, {"surface-lr", {"0.003", "1"}},
    {"grid-cells", {"32", "4097"}}, {"subdivision", {"3", "7"}}, {"train-views", {"5", "0"}},
    {"patch", {"16", "16385"}}, {"density-decay", {"0.5", "0"}}, {"density-loss", {"0.5", "1001"}},
    {"surface-batch", {"views", "0"}}, {"surface-freeze", {"11", "-2"}}, {"surface-until", {"4000", "-2"}}, {"refit", {"13000", "-2"}}, {"face-normals-until", {"12", "-2"}},
    {"surface-smoothness", {"0.1", "-1"}}, {"level-prior", {"1000", "inf"}}, {"level-prior-degree", {"4", "7"}}, {"level-prior-warp", {"0.1", "2"}}, {"anchor-mean-height", {"", ""}},
    {"water-sign-check", {"", ""}}, {"surface-gate", {"1.05", "-1"}}, {"restart-gate", {"0.99", "-1"}}, {"surface-agreement", {"2", "17"}}, {"level-prior-tilt-only", {"", ""}},
    {"known-water-scale", {"0.5", "-1"}}, {"sweep-loss", {"1", "-1"}}, {"sweep-loss-every", {"4", "0"}}, {"sweep-loss-only", {"", ""}}, {"sweep-watch", {"500", "-1"}}, {"water-scale-search", {"", ""}},
    {"octaves-open-until", {"13", "-2"}}, {"sh-interval", {"14", "-2"}}, {"density-reset-every", {"15", "-2"}},
    {"density-reset-until", {"16", "-2"}}, {"density-decay-every", {"17", "-2"}}, {"densify-from", {"18", "-2"}},
    {"densify-every", {"19", "-2"}}, {"densify-until", {"20", "-2"}}, {"no-densify", {"", ""}},
    {"densify-grad", {"0.001", "nan"}}, {"densify-strategy", {"mcmc", "gsplat"}}, {"prune-every", {"21", "-2"}}, {"prune-large-from", {"22", "-2"}},
    {"lr-steps", {"23", "-2"}}, {"restart-gaussians", {"30,60", "5,x"}}, {"progress-every", {"7", "0"}},
    {"eval-every", {"8", "-1"}}, {"checkpoint-every", {"9", "-1"}},
};

}  // namespace

TEST_CASE("train options: every flag's value survives config.json, and a bad one is refused naming the flag") {
  for (const TrainOption& o : trainOptionTable()) {
    if (o.flag.empty()) continue;
    INFO("--" << o.flag);
    auto sample = kSamples.find(o.flag);
    REQUIRE_MESSAGE(sample != kSamples.end(), "a new option needs a sample here, so its round trip is tested");
    const std::string name = "--" + o.flag;
    TrainConfig c = resolvedConfig();
    if (o.flag == "known-water-scale") c.model = WaterModel::KnownWater;  // what it needs beside it
    if (o.flag == "sweep-loss-only") c.sweepLoss = 1;
    const nlohmann::json before = o.get(c);
    o.set(c, o.parse(sample->second.first, name), name);
    CHECK(o.get(c) != before);  // the sample is not the default
    if (o.key.empty()) continue;  // a model switch: its key is "model", checked below
    TrainConfig back = trainConfigFromJson(trainConfigToJson(c), "test");
    CHECK(o.get(back) == o.get(c));
    const std::string bad = sample->second.second;
    if (bad.empty()) continue;
    TrainConfig d = resolvedConfig();
    CHECK_THROWS_WITH_AS(o.set(d, o.parse(bad, name), name), doctest::Contains(name.c_str()), Error);
  }
  TrainConfig c = resolvedConfig();
  findTrainOption("flat-water")->set(c, true, "--flat-water");
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").model == WaterModel::FlatWater);
}

TEST_CASE("train options: validation checks every row's range on a config set in code") {
  TrainConfig c = resolvedConfig();
  validateTrainConfig(c);
  c.kBuffer = 0;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--k-buffer must be between 1 and 64"), Error);
  c = resolvedConfig();
  c.surfaceLearningRate = 2;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--surface-lr must be in (0, 1)"), Error);
  c = resolvedConfig();
  c.densityResetValue = -1;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("density_reset_value"), Error);
  c = resolvedConfig();
  c.ior = 0.5;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("index of refraction"), Error);
}

TEST_CASE("train options: config.json without a required key, or with a value of the wrong type, is refused by name") {
  nlohmann::json j = trainConfigToJson(resolvedConfig());
  nlohmann::json missing = j;
  missing.erase("k_buffer");
  CHECK_THROWS_WITH_AS(trainConfigFromJson(missing, "RUN/config.json"), doctest::Contains("no \"k_buffer\""), Error);
  nlohmann::json wrong = j;
  wrong["schedule"]["lr_steps"] = "many";
  CHECK_THROWS_WITH_AS(trainConfigFromJson(wrong, "RUN/config.json"), doctest::Contains("RUN/config.json: schedule/lr_steps"), Error);
  nlohmann::json huge = j;
  huge["initial_gaussians"] = 1e12;  // a float where an integer belongs
  CHECK_THROWS_WITH_AS(trainConfigFromJson(huge, "RUN/config.json"), doctest::Contains("initial_gaussians must be an integer"), Error);
  nlohmann::json old = j;  // runs from before an option: its default
  old.erase("hit_records");
  CHECK(trainConfigFromJson(old, "old").hitRecordsPerRay == TrainConfig{}.hitRecordsPerRay);
}

TEST_CASE("train options: the command line parses through the table, and --help lists every flag") {
  test::CliResult bad = test::runCli("train /nonexistent -o /tmp/never --surface-lr 2");
  CHECK(bad.exitCode != 0);
  CHECK(bad.output.find("--surface-lr must be in (0, 1), got 2") != std::string::npos);
  test::CliResult both = test::runCli("train /nonexistent -o /tmp/never --flat-water --no-refraction");
  CHECK(both.exitCode != 0);
  CHECK(both.output.find("exclude each other") != std::string::npos);
  test::CliResult help = test::runCli("train --help");
  REQUIRE(help.exitCode == 0);
  for (const TrainOption& o : trainOptionTable())
    if (!o.flag.empty()) CHECK_MESSAGE(help.output.find("--" + o.flag + " ") != std::string::npos, "--" << o.flag);
  CHECK(help.output.find("--max-gaussians N            cap on the Gaussian count (enforced by densification) (default from the data: the initial count") != std::string::npos);
}
