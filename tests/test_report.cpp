// refrax report (training runs flattened into CSV rows), the evaluations a run records for
// the accuracy-against-time curve (metrics.json "evaluations"), and --density-loss.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/report/csv_table.h"
#include "engine/report/run_report.h"
#include "engine/train/train_run.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace fs = std::filesystem;

namespace refrax {
namespace {

using test::TrainTempDir;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A run folder as `refrax train` leaves it (only the files report reads).
void fakeRun(const std::string& dir, double psnr, bool withSurface, int evaluations) {
  fs::create_directories(dir);
  nlohmann::json c = {{"steps", 300}, {"patch", 32}, {"max_sh_degree", 0}, {"mlp_width", 64}, {"mlp_hidden_layers", 3},
                      {"mlp_octaves", 6}, {"grid_cells", 64}, {"subdivision_levels", 2}, {"density_loss", 0.007},
                      {"schedule", {{"face_normals_until", 150}}}, {"ior", 1.1}, {"seed", 1}};
  writeJson(dir + "/config.json", c);
  nlohmann::json m = {{"model", "refraction"}, {"step", 300}, {"psnr", psnr}, {"ssim", 0.8}, {"gaussians", 2000},
                      {"model_bytes", 123456789}, {"training_seconds", 61.5}, {"missed_rays", 0}};
  if (withSurface) {
    m["surface_rmse"] = 0.0125;
    m["initial_flat_surface_rmse"] = 0.02;
  }
  m["evaluations"] = nlohmann::json::array();
  for (int e = 1; e <= evaluations; e++) {
    nlohmann::json p = {{"step", 100 * e}, {"seconds", 20.0 * e}, {"psnr", psnr - 3 + e}, {"ssim", 0.7}};
    if (withSurface) p["surface_rmse"] = 0.02 / e;
    m["evaluations"].push_back(p);
  }
  writeJson(dir + "/metrics.json", m);
}

}  // namespace

TEST_CASE("report: one row per run, or per evaluation, with empty cells for what a run lacks") {
  TrainTempDir dir;
  fakeRun(dir / "defaults", 21.25, true, 3);
  fakeRun(dir / "plain", 17.5, false, 2);
  ReportRequest r;
  r.runs = {dir / "defaults", dir / "plain/"};
  r.extra = parseReportColumns("config=a b,preset=nerfrac-hybrid");
  writeReportCsv(dir / "runs.csv", r, false);
  CsvTable t = readCsv(dir / "runs.csv");
  REQUIRE(t.rows.size() == 2);
  CHECK(t.header[0] == "run");
  CHECK(t.header[1] == "config");
  CHECK(t.header[2] == "preset");
  auto at = [&](size_t row, const std::string& col) { return t.rows[row][csvColumn(t, col)]; };
  CHECK(at(0, "run") == "defaults");
  CHECK(at(1, "run") == "plain");
  CHECK(at(0, "config") == "a b");
  CHECK(at(0, "psnr") == "21.25");
  CHECK(at(0, "surface_rmse") == "0.0125");
  CHECK(at(1, "surface_rmse") == "");
  CHECK(at(0, "model_bytes") == "123456789");
  CHECK(at(0, "config_face_normals_until") == "150");
  CHECK(at(0, "config_density_loss") == "0.007");
  CHECK(at(0, "water_removal_psnr") == "");

  // Appending keeps the rows there; other columns are refused and leave the file as it was.
  writeReportCsv(dir / "runs.csv", r, true);
  CHECK(readCsv(dir / "runs.csv").rows.size() == 4);
  std::string before = readFile(dir / "runs.csv");
  ReportRequest other = r;
  other.extra = parseReportColumns("config=x");
  CHECK(errorOf([&] { writeReportCsv(dir / "runs.csv", other, true); }).find("has other columns than this report") != std::string::npos);
  CHECK(readFile(dir / "runs.csv") == before);

  // Per evaluation: 3 + 2 rows, the curve's values in the eval_ columns.
  r.evaluations = true;
  writeReportCsv(dir / "evals.csv", r, false);
  CsvTable e = readCsv(dir / "evals.csv");
  REQUIRE(e.rows.size() == 5);
  CHECK(e.rows[2][csvColumn(e, "eval_step")] == "300");
  CHECK(e.rows[2][csvColumn(e, "eval_seconds")] == "60");
  CHECK(e.rows[2][csvColumn(e, "eval_psnr")] == "21.25");
  CHECK(e.rows[1][csvColumn(e, "eval_surface_rmse")] == "0.01");
  CHECK(e.rows[4][csvColumn(e, "eval_surface_rmse")] == "");
  CHECK(e.rows[4][csvColumn(e, "run")] == "plain");

  // Errors name the run and write nothing.
  r.runs.push_back(dir / "missing");
  CHECK(errorOf([&] { writeReportCsv(dir / "new.csv", r, false); }) == dir / "missing" + " has no metrics.json (not a finished training run)");
  CHECK_FALSE(fileExists(dir / "new.csv"));
  CHECK(errorOf([] { parseReportColumns("config=a,nokey"); }) == "--set expects key=value[,key=value...], got 'nokey'");
  CHECK(errorOf([] { parseReportColumns("=v"); }) == "--set expects key=value[,key=value...], got '=v'");
  fakeRun(dir / "old", 20, true, 0);
  r.runs = {dir / "old"};
  CHECK(errorOf([&] { writeReportCsv(dir / "new.csv", r, false); }).find("has no evaluations") != std::string::npos);

  // The CLI writes the same file, and fails with one line.
  auto ok = test::runCli("report " + dir / "defaults" + " " + dir / "plain" + " -o " + dir / "cli.csv" + " --set config=a\\ b,preset=nerfrac-hybrid");
  CHECK(ok.exitCode == 0);
  CHECK(readFile(dir / "cli.csv") == readFile(dir / "runs.csv").substr(0, readFile(dir / "cli.csv").size()));
  auto bad = test::runCli("report " + dir / "missing" + " -o " + dir / "cli2.csv");
  CHECK(bad.exitCode != 0);
  CHECK(bad.output.find("refrax: error: " + dir / "missing" + " has no metrics.json") != std::string::npos);
}

TEST_CASE("train: --eval-every records each evaluation with its training seconds, and report charts them" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  nlohmann::json m = test::trainAndReadMetrics(data, dir / "run",
                                               " --steps 12 --eval-every 5 --gaussians 300 --patch 16 --sh-degree 0 --checkpoint-every 0 --progress-every 100");
  REQUIRE(m.contains("evaluations"));
  const auto& e = m["evaluations"];
  REQUIRE(e.size() == 3);  // steps 5, 10, and the final 12
  CHECK(e[0]["step"] == 5);
  CHECK(e[1]["step"] == 10);
  CHECK(e[2]["step"] == 12);
  CHECK(e[2]["psnr"].get<double>() == m["psnr"].get<double>());
  CHECK(e[2]["surface_rmse"].get<double>() == m["surface_rmse"].get<double>());
  CHECK(e[2]["seconds"].get<double>() == m["training_seconds"].get<double>());
  for (size_t i = 0; i < e.size(); i++) {
    CHECK(std::isfinite(e[i]["psnr"].get<double>()));
    CHECK(e[i]["surface_rmse"].get<double>() > 0);
    CHECK(e[i]["seconds"].get<double>() > 0);
    if (i) CHECK(e[i]["seconds"].get<double>() > e[i - 1]["seconds"].get<double>());
  }
  // RUN/evaluations.json holds the intermediate ones; a resumed run keeps those before its step.
  CHECK(readJson(dir / "run/evaluations.json").size() == 2);
  CHECK(readEvaluations(dir / "run", 9).size() == 1);
  CHECK(readEvaluations(dir / "nowhere", 100).empty());

  auto r = test::runCli("report " + dir / "run" + " -o " + dir / "curve.csv --evaluations --set config=defaults");
  REQUIRE(r.exitCode == 0);
  auto c = test::runCli("chart " + dir / "curve.csv" + " -o " + dir / "curve.svg --x eval_seconds --y eval_psnr --series config");
  INFO(c.output);
  CHECK(c.exitCode == 0);
  CHECK(readFile(dir / "curve.svg").find("data-series=\"defaults\"") != std::string::npos);
}

GPU_TEST_CASE("train: --density-loss weighs the density loss, 0 switches it off, and survives config.json" * doctest::test_suite("one-backend")) {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig base = test::sessionConfig(data, 10, 200, 16, rng(), d);
  base.maxShDegree = 0;
  std::map<double, std::vector<double>> after;  // density logits after one step, per weight
  for (double weight : {0.0, 0.007, 50.0}) {
    CAPTURE(weight);
    TrainConfig c = base;
    c.densityLossWeight = weight;
    auto s = createTrainSession(ctx, c, d);  // same seed: same Gaussians, view and patch
    size_t n = s->model.gaussians.count();
    double squares = 0;
    for (size_t i = 0; i < n; i++) {
      double sg = 1 / (1 + std::exp(-double(s->model.gaussians.at(i)[f32::kGaussLogitDensity])));
      squares += sg * sg;
    }
    StepResult r = trainStep(*s);
    // The loss reported is the image loss plus weight * mean(density^2) of the Gaussians stepped.
    CHECK(r.loss - r.imageLoss == doctest::Approx(weight * squares / double(n)).epsilon(1e-4).scale(1e-7));
    pullGaussians(*s);  // the device stepped them
    for (size_t i = 0; i < n; i++) after[weight].push_back(s->model.gaussians.at(i)[f32::kGaussLogitDensity]);
  }
  // Adam's first step moves each logit by the learning rate against the sign of its gradient.
  // The density loss adds a positive term to every logit's gradient, so with it no density
  // ends higher than without it, and the Gaussians no ray saw (no image gradient) go down.
  REQUIRE(after[0.0].size() == after[50.0].size());
  size_t lower = 0;
  for (size_t i = 0; i < after[0.0].size(); i++) {
    CHECK(after[50.0][i] <= after[0.0][i] + 1e-6);
    lower += after[50.0][i] < after[0.0][i] - 1e-3;
  }
  CHECK(lower > after[0.0].size() / 10);
  TrainConfig c = base;
  c.densityLossWeight = 0;
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").densityLossWeight == 0);
  nlohmann::json old = trainConfigToJson(base);
  old.erase("density_loss");
  CHECK(trainConfigFromJson(old, "old").densityLossWeight == 0.007);  // runs from before the option
  for (double bad : {-1e-3, double(NAN), 1e4}) {
    c.densityLossWeight = bad;
    CHECK_THROWS_AS(validateTrainConfig(c), Error);
  }
}

}  // namespace refrax
