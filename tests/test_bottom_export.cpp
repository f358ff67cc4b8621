// refrax export RUN --bottom DIR (engine/survey/): on the tiny preset, every GeoTIFF read back
// by GDAL (a reader that is not ours) on the truth's grid, each value at the truth's vertex, the
// bottom against bottom_gt_height.npy as bottom.json reports it, the CRS and origin when given,
// the point cloud, and one clear error for bad options.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/io/ply_points.h"
#include "tests/gdal_test_util.h"
#include "tests/train_test_util.h"

using namespace refrax;
using test::gdalInfo;
using test::gdalXyz;
namespace fs = std::filesystem;

namespace {

// Which truth vertex GDAL's coordinate is: an index that must be whole (a map off the grid by
// any part of a cell is not on the truth's vertices).
long vertexIndex(double coordinate, double lo, double spacing) {
  const double f = (coordinate - lo) / spacing;
  CHECK(std::abs(f - std::round(f)) < 1e-3);
  return std::lround(f);
}

}  // namespace

TEST_CASE("bottom export: GDAL reads each layer on the truth's grid, and the bottom against the truth as bottom.json says" *
          doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  REQUIRE(test::runCli("train " + data + " -o " + (dir / "run") + " --steps 300 --gaussians 2000 --patch 32 --checkpoint-every 0").exitCode == 0);
  const test::CliResult r = test::runCli("export " + (dir / "run") + " --bottom " + (dir / "bed"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const fs::path bed = dir.path / "bed";
  const nlohmann::json water = readJson(data + "/water.json");
  const NpyArray truth = readNpy(data + "/bottom_gt_height.npy");
  const size_t n = truth.shape[0];
  const double x0 = water["domain"][0], y0 = water["domain"][1], x1 = water["domain"][2], y1 = water["domain"][3];
  const double dx = (x1 - x0) / double(n - 1), dy = (y1 - y0) / double(n - 1);
  for (const char* f : {"bottom_elevation", "water_surface", "water_depth", "confidence", "ortho_dry", "ortho_wet"}) {
    INFO(f);
    const nlohmann::json info = gdalInfo(bed / (std::string(f) + ".tif"), "proj_get_ellipsoid");  // a local frame (test_geotiff.cpp)
    CHECK(info["size"] == nlohmann::json({n, n}));
    CHECK(info["metadata"][""]["AREA_OR_POINT"] == "Point");
    CHECK(info["geoTransform"][0].get<double>() == doctest::Approx(x0 - dx / 2));
    CHECK(info["geoTransform"][3].get<double>() == doctest::Approx(y1 + dy / 2));
    const bool ortho = std::string(f).rfind("ortho", 0) == 0;
    CHECK(info["bands"].size() == (std::string(f) == "confidence" || ortho ? 3u : 1u));
    CHECK(info["bands"][0]["type"] == (ortho ? "Byte" : "Float32"));
    if (!ortho) CHECK(info["bands"][0]["noDataValue"] == "NaN");
  }
  CHECK(gdalInfo(bed / "bottom_elevation.tif", "proj_get_ellipsoid")["bands"][0]["description"] == "bottom elevation");
  CHECK(gdalInfo(bed / "bottom_elevation.tif", "proj_get_ellipsoid")["bands"][0]["unit"] == "m");
  // The bottom as GDAL reads it, each value at its truth vertex, against the truth where a
  // training view sees: what bottom.json reports.
  const auto z = gdalXyz(bed / "bottom_elevation.tif", 1), views = gdalXyz(bed / "confidence.tif", 2);
  REQUIRE(z.size() == n * n);
  REQUIRE(views.size() == n * n);
  double se = 0, sum = 0;
  size_t cells = 0, seen = 0;
  for (size_t k = 0; k < z.size(); k++) {
    const long i = vertexIndex(z[k][0], x0, dx), j = vertexIndex(z[k][1], y0, dy);
    REQUIRE((i >= 0 && i < long(n) && j >= 0 && j < long(n)));
    const double t = truth.data[size_t(j) * n + size_t(i)];
    if (!std::isfinite(t) || views[k][2] < 1) continue;
    seen++;
    if (!std::isfinite(z[k][2])) continue;
    se += (z[k][2] - t) * (z[k][2] - t), sum += z[k][2] - t, cells++;
  }
  const nlohmann::json report = readJson((bed / "bottom.json").string());
  const nlohmann::json& acc = report["accuracy"];
  INFO(acc.dump());
  REQUIRE(cells > 0);
  CHECK(acc["bottom_cells"].get<size_t>() == cells);
  CHECK(acc["bottom_rmse_m"].get<double>() == doctest::Approx(std::sqrt(se / double(cells))).epsilon(1e-4));
  CHECK(acc["bottom_bias_m"].get<double>() == doctest::Approx(sum / double(cells)).epsilon(1e-4));
  CHECK(acc["bottom_coverage"].get<double>() == doctest::Approx(double(cells) / double(seen)));
  // How well 300 tiny steps map the bed (lavapipe, seed 1, two runs): RMSE 0.18 and 0.24 m,
  // 0.37 and 0.49 of the 0.49 m water depth, coverage 83% and 76%, the water-free orthophoto
  // 14.2 and 14.9 dB over all vertices. Bounds that hold the plumbing, not the method (the
  // full-size study is docs/experiments/, a GPU's job): a bed no worse than the depth itself.
  CHECK(acc["bottom_rmse_share"].get<double>() < 1.0);
  CHECK(acc["bottom_coverage"].get<double>() > 0.5);
  CHECK(acc["ortho_dry_psnr"].get<double>() > 10.0);
  // the point cloud: the mapped vertices, at their elevation
  const std::vector<PlyPoint> points = readPlyPoints((bed / "bottom.ply").string());
  CHECK(points.size() == report["points"].get<size_t>());
  CHECK(points.size() == n * n - report["layers"]["bottom_elevation"]["no_data_vertices"].get<size_t>());

  // In a projected CRS: the same grid shifted by the origin, the CRS in every file.
  const test::CliResult utm = test::runCli("export " + (dir / "run") + " --bottom " + (dir / "utm") + " --crs EPSG:32633 --origin 500000,4649776,12.5");
  INFO(utm.output);
  REQUIRE(utm.exitCode == 0);
  const nlohmann::json info = gdalInfo(fs::path(dir / "utm") / "water_depth.tif");
  CHECK(info["coordinateSystem"]["wkt"].get<std::string>().find("ID[\"EPSG\",32633]") != std::string::npos);
  const auto shifted = gdalXyz(fs::path(dir / "utm") / "bottom_elevation.tif", 1);
  REQUIRE(shifted.size() == z.size());
  CHECK(shifted[0][0] == doctest::Approx(z[0][0] + 500000));
  CHECK(shifted[0][1] == doctest::Approx(z[0][1] + 4649776));
  for (size_t k = 0; k < z.size(); k++)
    if (std::isfinite(z[k][2])) CHECK(shifted[k][2] == doctest::Approx(z[k][2] + 12.5).epsilon(1e-6));

  // bad options: one error each, nothing written
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + (dir / "b1") + " --glb " + (dir / "x.glb")), "one of --glb");
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + (dir / "b2") + " --grid 1"), "--grid");
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + (dir / "b3") + " --crs EPSG:32633"), "go together");
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + (dir / "b4") + " --crs UTM33 --origin 1,2"), "--crs UTM33");
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + (dir / "b5") + " --crs EPSG:32633 --origin 1,x"), "--origin 1,x");
  test::checkOneError(test::runCli("export " + (dir / "run") + " --bottom " + bed.string()), "--bottom");  // not empty
  for (const char* b : {"b1", "b2", "b3", "b4", "b5"}) CHECK(!fs::exists(dir / b));
}
