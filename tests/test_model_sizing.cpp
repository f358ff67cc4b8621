// The model's size from the data (engine/train/model_sizing.h): the pixel footprint on the water,
// each rule on hand-computed numbers, the given options kept, and the choice in a run's
// config.json and log.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "engine/base/error.h"
#include "engine/io/json_io.h"
#include "engine/train/model_sizing.h"
#include "engine/run/train_config.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

// A camera at `height` above the origin looking straight down (-z), image `w` x `h`, focal `f`:
// every pixel covers height / f metres on the plane z = 0 (its rays' spacing there).
Camera nadirCamera(double height, double f, int w, int h, double x = 0) {
  Camera c;
  c.cameraToWorld[0] = glm::dvec4(1, 0, 0, 0);   // right
  c.cameraToWorld[1] = glm::dvec4(0, 1, 0, 0);   // up
  c.cameraToWorld[2] = glm::dvec4(0, 0, 1, 0);   // back: looks down -z
  c.cameraToWorld[3] = glm::dvec4(x, 0, height, 1);
  c.fx = c.fy = f;
  c.cx = w / 2.0;
  c.cy = h / 2.0;
  c.width = w;
  c.height = h;
  return c;
}

const Rect kDomain{-1, -1, 1, 1};  // 2 m a side

}  // namespace

TEST_CASE("model sizing: a pixel's footprint on the water is height / focal straight down, the median over the views") {
  CHECK(medianPixelFootprint({nadirCamera(5, 500, 640, 480)}, 0, kDomain) == doctest::Approx(0.01).epsilon(1e-9));
  // The plane moves up: the footprint shrinks with the distance to it.
  CHECK(medianPixelFootprint({nadirCamera(5, 500, 640, 480)}, 1, kDomain) == doctest::Approx(0.008).epsilon(1e-9));
  // Three views, each with all 81 samples inside a wide domain: the median (0.01) of 0.004, 0.01, 0.04.
  const Rect wide{-100, -100, 100, 100};
  CHECK(medianPixelFootprint({nadirCamera(2, 500, 640, 480), nadirCamera(5, 500, 640, 480), nadirCamera(20, 500, 640, 480)}, 0, wide) ==
        doctest::Approx(0.01).epsilon(1e-9));
  // A view whose samples all land outside the domain does not count; a view looking away sees no water.
  CHECK(medianPixelFootprint({nadirCamera(5, 500, 64, 64, 50), nadirCamera(5, 500, 640, 480)}, 0, kDomain) == doctest::Approx(0.01).epsilon(1e-9));
  Camera up = nadirCamera(5, 500, 64, 64);
  up.cameraToWorld[2] = glm::dvec4(0, 0, -1, 0);
  CHECK(medianPixelFootprint({up}, 0, kDomain) == 0);
  CHECK_THROWS_WITH_AS(sizeModelFromData({up}, 0, kDomain), doctest::Contains("no training view sees the water's domain"), Error);
}

TEST_CASE("model sizing: octaves, grid, subdivision and Gaussians follow the footprint and the image size") {
  // Footprint 0.01 m on a 2 m domain: the shortest resolvable wave is 22 x 0.01 = 0.22 m;
  // 2 / 2^(L-1) <= 0.22 first at L = 5 (0.125 m; L = 4 gives 0.25). Grid 2^5 = 32 cells of
  // 0.0625 m; 0.0625 / 2^K nearest 2 x 0.01 at K = 2 (log2 3.1 = 1.6). 640 x 480 / 8 = 38,400
  // Gaussians (38,000 to two significant figures), drawn whole at the start and kept as the cap.
  ModelSizing s = sizeModelFromData({nadirCamera(5, 500, 640, 480)}, 0, kDomain);
  CHECK(s.pixelFootprint == doctest::Approx(0.01));
  CHECK(s.pixelsPerView == 307200);
  CHECK(s.mlpOctaves == 5);
  CHECK(s.gridCells == 32);
  CHECK(s.subdivisionLevels == 2);
  CHECK(s.initialGaussians == 38000);
  CHECK(s.maxGaussians == 38000);
  REQUIRE(s.choices.size() == sizedConfigKeys().size());
  for (size_t i = 0; i < s.choices.size(); i++) {
    CHECK(s.choices[i].key == sizedConfigKeys()[i]);
    CHECK(!s.choices[i].reason.empty());
  }
  // Four times closer: the footprint 0.0025 m resolves 0.055 m waves, L = 7 (0.03125 m).
  CHECK(sizeModelFromData({nadirCamera(1.25, 500, 640, 480)}, 0, kDomain).mlpOctaves == 7);
  // A small image: at least 1,000 Gaussians; a far camera: at least 2 octaves, no subdivision.
  ModelSizing far = sizeModelFromData({nadirCamera(200, 500, 64, 64)}, 0, kDomain);
  CHECK(far.initialGaussians == 1000);  // 4,096 / 8 = 512
  CHECK(far.maxGaussians == 1000);
  CHECK(far.mlpOctaves == kMinOctaves);
  CHECK(far.gridCells == 4);
  CHECK(far.subdivisionLevels == 0);
  // Counts are rounded to two significant figures.
  CHECK(sizeModelFromData({nadirCamera(5, 500, 1001, 999)}, 0, kDomain).initialGaussians == 120000);  // 124,999.9
}

// A default configuration, changed by `given`, sized from one nadir view (footprint 0.01 m over
// kDomain) for `keys`.
TrainConfig sizedFromOneView(const std::set<std::string>& keys, const std::function<void(TrainConfig&)>& given) {
  TrainConfig c;
  c.domain = kDomain;
  given(c);
  c.sizeFromData = keys;
  applyModelSizing(c, {nadirCamera(5, 500, 640, 480)});
  return c;
}

TEST_CASE("model sizing: only the options left to the data change, and a given count bounds the other") {
  TrainConfig c;
  c.waterHeight = 0;
  c.domain = kDomain;
  c.mlpOctaves = 6;
  c.mlpCoarseOctaves = 6;  // coarse-to-fine off: it follows the octaves
  c.gridCells = 64;
  c.initialGaussians = 20000;  // given
  c.sizeFromData = {"max_gaussians", "mlp_octaves", "subdivision_levels"};
  applyModelSizing(c, {nadirCamera(5, 500, 640, 480)});
  CHECK(c.sizeFromData.empty());
  CHECK(c.mlpOctaves == 5);
  CHECK(c.mlpCoarseOctaves == 5);
  CHECK(c.gridCells == 64);  // given
  CHECK(c.subdivisionLevels == 2);
  CHECK(c.initialGaussians == 20000);
  CHECK(c.maxGaussians == 38000);
  CHECK(c.modelSizing["pixel_footprint"].get<double>() == doctest::Approx(0.01));
  CHECK(c.modelSizing["derived"].size() == 3);
  CHECK(c.modelSizing["derived"]["mlp_octaves"]["value"].get<double>() == 5);
  CHECK(!c.modelSizing["derived"].contains("grid_cells"));

  SUBCASE("a given initial count above the derived cap raises the cap") {
    TrainConfig d = sizedFromOneView({"max_gaussians"}, [](TrainConfig& g) { g.initialGaussians = 50000; });
    CHECK(d.maxGaussians == 50000);
    CHECK(d.modelSizing["derived"]["max_gaussians"]["reason"].get<std::string>().find("raised") != std::string::npos);
  }
  SUBCASE("a given cap below the derived initial count lowers the count") {
    TrainConfig d = sizedFromOneView({"initial_gaussians"}, [](TrainConfig& g) { g.maxGaussians = 1000; });
    CHECK(d.initialGaussians == 1000);
  }
  SUBCASE("coarse-to-fine on: the coarse octaves stay") {
    TrainConfig d = sizedFromOneView({"mlp_octaves"}, [](TrainConfig& g) { g.mlpCoarseOctaves = 3; });
    CHECK(d.mlpOctaves == 5);
    CHECK(d.mlpCoarseOctaves == 3);
  }
  SUBCASE("straight rays size only the Gaussians, a flat plane no height field") {
    const std::set<std::string> all(sizedConfigKeys().begin(), sizedConfigKeys().end());
    TrainConfig d = sizedFromOneView(all, [](TrainConfig& g) { g.model = WaterModel::NoRefraction; });
    CHECK(d.initialGaussians == 38000);
    CHECK(d.mlpOctaves == TrainConfig{}.mlpOctaves);
    CHECK(d.gridCells == TrainConfig{}.gridCells);
    TrainConfig f = sizedFromOneView(all, [](TrainConfig& g) { g.model = WaterModel::FlatWater; });
    CHECK(f.gridCells == 32);
    CHECK(f.mlpOctaves == TrainConfig{}.mlpOctaves);
  }
  SUBCASE("nothing left to the data: nothing derived, nothing recorded") {
    TrainConfig d = sizedFromOneView({}, [](TrainConfig&) {});
    CHECK(d.modelSizing.is_null());
    CHECK(d.mlpOctaves == TrainConfig{}.mlpOctaves);
  }
}

GPU_TEST_CASE("model sizing: refrax train prints the derived size with its reasons, and config.json keeps it through a resume" *
              doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine"), run = dir / "sized";
  test::CliResult r = test::runCli("train " + data + " -o " + run + " --steps 4 --patch 16 --checkpoint-every 2 --gaussians 300 --mlp-octaves 3");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(r.output.find("model size from the data: --max-gaussians") != std::string::npos);
  CHECK(r.output.find("model size from the data: --grid-cells") != std::string::npos);
  CHECK(r.output.find("model size from the data: --mlp-octaves") == std::string::npos);  // given
  CHECK(r.output.find("model size from the data: --gaussians") == std::string::npos);   // given
  const nlohmann::json config = readJson(run + "/config.json");
  REQUIRE(config.contains("model_sizing"));
  const nlohmann::json& derived = config["model_sizing"]["derived"];
  CHECK(config["mlp_octaves"] == 3);
  CHECK(config["initial_gaussians"] == 300);
  CHECK(config["grid_cells"].get<double>() == derived["grid_cells"]["value"].get<double>());
  CHECK(config["max_gaussians"].get<double>() == derived["max_gaussians"]["value"].get<double>());
  CHECK(config["model_sizing"]["pixel_footprint"].get<double>() > 0);
  // The tiny preset's footprint (about 0.013 m on its 2 m domain) gives 16 cells; the given 3 octaves do not move it.
  CHECK(config["grid_cells"] == 16);

  test::CliResult resumed = test::runCli("train --resume " + run + " --steps 6");
  INFO(resumed.output);
  REQUIRE(resumed.exitCode == 0);
  CHECK(resumed.output.find("model size from the data") == std::string::npos);  // decided once, at the start
  const nlohmann::json after = readJson(run + "/config.json");
  CHECK(after["model_sizing"] == config["model_sizing"]);
  CHECK(after["grid_cells"] == config["grid_cells"]);
}

}  // namespace refrax
