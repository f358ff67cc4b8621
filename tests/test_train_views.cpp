// refrax train --train-views N (number-of-views sweeps): an even spread of N training views,
// kept through config.json and a resume, validated against the dataset.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "engine/dataset/dataset.h"
#include "engine/base/error.h"
#include "engine/io/json_io.h"
#include "engine/run/train_config.h"
#include "engine/train/train_run.h"
#include "engine/train/train_session.h"
#include "engine/run/train_views.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

TEST_CASE("train views: the spread takes the first and the last and is even in between") {
  CHECK(spreadViewIndices(8, 1) == std::vector<size_t>{0});
  CHECK(spreadViewIndices(8, 2) == std::vector<size_t>{0, 7});
  CHECK(spreadViewIndices(8, 4) == std::vector<size_t>{0, 2, 5, 7});
  CHECK(spreadViewIndices(8, 8) == std::vector<size_t>{0, 1, 2, 3, 4, 5, 6, 7});
  std::mt19937 rng(test::freshSeed());
  for (int trial = 0; trial < 200; trial++) {
    size_t available = std::uniform_int_distribution<size_t>(1, 60)(rng);
    size_t count = std::uniform_int_distribution<size_t>(1, available)(rng);
    std::vector<size_t> v = spreadViewIndices(available, count);
    INFO(available << " " << count);
    REQUIRE(v.size() == count);
    CHECK(v.front() == 0);
    if (count > 1) CHECK(v.back() == available - 1);
    // Distinct, increasing, and no gap more than one index wider than any other.
    size_t minGap = available, maxGap = 0;
    for (size_t i = 1; i < v.size(); i++) {
      CHECK(v[i] > v[i - 1]);
      minGap = std::min(minGap, v[i] - v[i - 1]);
      maxGap = std::max(maxGap, v[i] - v[i - 1]);
    }
    if (count > 1) CHECK(maxGap - minGap <= 1);
  }
  CHECK_THROWS_WITH_AS(spreadViewIndices(8, 0), doctest::Contains("--train-views must be between 1 and 8"), Error);
  CHECK_THROWS_WITH_AS(spreadViewIndices(8, 9), doctest::Contains("--train-views must be between 1 and 8"), Error);
}

GPU_TEST_CASE("train: --train-views N trains on N of the views, survives config.json and a resume, and is validated" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset full = loadDataset(data);
  Dataset kept = loadDataset(data);
  keepTrainViews(kept, 3);
  REQUIRE(kept.split("train").size() == 3);
  const auto& all = full.split("train");
  for (size_t k = 0; k < 3; k++) CHECK(kept.split("train")[k].name == all[spreadViewIndices(all.size(), 3)[k]].name);
  CHECK(kept.split("test").size() == full.split("test").size());
  Dataset untouched = loadDataset(data);
  keepTrainViews(untouched, 0);
  CHECK(untouched.split("train").size() == all.size());

  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "two") + " --train-views 2 --steps 2 --gaussians 200 --patch 16 --sh-degree 0");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(r.output.find("2 training views") != std::string::npos);
  TrainConfig c = readRunConfig(dir / "two");
  CHECK(c.trainViews == 2);
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").trainViews == 2);
  auto session = openRun(ctx, dir / "two");
  REQUIRE(session->dataset.split("train").size() == 2);
  CHECK(session->dataset.split("train")[0].name == all.front().name);
  CHECK(session->dataset.split("train")[1].name == all.back().name);

  for (const char* bad : {"0", "-1", "9"}) {
    test::CliResult b = test::runCli("train " + data + " -o " + (dir / "bad") + " --train-views " + bad + " --steps 2 --gaussians 100");
    INFO(bad << ": " << b.output);
    CHECK(b.exitCode != 0);
    CHECK(b.output.find("--train-views must be") != std::string::npos);
    CHECK(std::count(b.output.begin(), b.output.end(), '\n') == 1);
    CHECK(!fs::exists(dir / "bad"));
  }
}
