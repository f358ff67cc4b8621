// GeoTIFF out (engine/io/geotiff.h), read back by GDAL (gdalinfo, gdal_translate from Debian's
// gdal-bin): the size, type, no-data, band names and units, the georeference (each value at its
// grid vertex), the CRS when one is given, and every value.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/geotiff.h"
#include "tests/gdal_test_util.h"

using namespace refrax;
using test::gdalInfo;
using test::gdalXyz;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("refrax_geotiff_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

}  // namespace

TEST_CASE("GeoTIFF: GDAL reads a float grid's size, no-data, bands and every value at its vertex") {
  TempDir dir;
  GeoGrid g;
  g.width = 5, g.height = 3, g.x0 = 1.0, g.yTop = 2.0, g.dx = 0.5, g.dy = 0.25;
  std::vector<float> values(2 * 15);
  for (uint32_t r = 0; r < 3; r++)
    for (uint32_t c = 0; c < 5; c++) values[2 * (r * 5 + c)] = float(10 * r + c) + 0.125f, values[2 * (r * 5 + c) + 1] = -float(r);
  values[2 * 7] = NAN;
  const fs::path f = dir.path / "grid.tif";
  writeGeoTiffFloat(f.string(), g, {{"bottom elevation", "m"}, {"views", ""}}, values, {{"REFRAX_FRAME", "test frame"}});
  const nlohmann::json info = gdalInfo(f, "proj_get_ellipsoid");  // a local frame: see the last case
  CHECK(info["size"] == nlohmann::json({5, 3}));
  REQUIRE(info["bands"].size() == 2);
  CHECK(info["bands"][0]["type"] == "Float32");
  CHECK(info["bands"][0]["description"] == "bottom elevation");
  CHECK(info["bands"][0]["unit"] == "m");
  CHECK(info["bands"][1]["description"] == "views");
  CHECK(info["bands"][0]["noDataValue"] == "NaN");
  CHECK(info["metadata"][""]["REFRAX_FRAME"] == "test frame");
  CHECK(info["metadata"][""]["AREA_OR_POINT"] == "Point");
  // Values are samples at the vertices: GDAL's pixel (0, 0) is centred on (x0, yTop).
  const auto& t = info["geoTransform"];
  CHECK(t[0].get<double>() == doctest::Approx(1.0 - 0.25));
  CHECK(t[1].get<double>() == doctest::Approx(0.5));
  CHECK(t[3].get<double>() == doctest::Approx(2.0 + 0.125));
  CHECK(t[5].get<double>() == doctest::Approx(-0.25));
  const auto xyz = gdalXyz(f, 1);
  REQUIRE(xyz.size() == 15);
  for (size_t k = 0; k < 15; k++) {
    const size_t r = k / 5, c = k % 5;
    INFO("pixel " << k << ": " << xyz[k][0] << " " << xyz[k][1] << " " << xyz[k][2]);
    CHECK(xyz[k][0] == doctest::Approx(1.0 + 0.5 * double(c)));
    CHECK(xyz[k][1] == doctest::Approx(2.0 - 0.25 * double(r)));
    if (k == 7) CHECK(std::isnan(xyz[k][2]));
    else CHECK(xyz[k][2] == doctest::Approx(values[2 * k]));
  }
  const auto second = gdalXyz(f, 2);
  REQUIRE(second.size() == 15);
  CHECK(second[14][2] == doctest::Approx(-2.0));
}

TEST_CASE("GeoTIFF: an RGB orthophoto in a projected CRS reads back as three bytes per pixel in that CRS") {
  TempDir dir;
  GeoGrid g;
  g.width = 4, g.height = 2, g.x0 = 500000.0, g.yTop = 4649776.0, g.dx = 0.1, g.dy = 0.1, g.epsg = 32633;
  std::vector<uint8_t> rgb(24);
  for (size_t k = 0; k < rgb.size(); k++) rgb[k] = uint8_t(10 * k);
  const fs::path f = dir.path / "ortho.tif";
  writeGeoTiffRgb8(f.string(), g, rgb);
  const nlohmann::json info = gdalInfo(f);
  CHECK(info["size"] == nlohmann::json({4, 2}));
  REQUIRE(info["bands"].size() == 3);
  CHECK(info["bands"][0]["type"] == "Byte");
  CHECK(info["bands"][0]["colorInterpretation"] == "Red");
  CHECK(info["bands"][2]["colorInterpretation"] == "Blue");
  CHECK(!info["bands"][0].contains("noDataValue"));
  const std::string wkt = info["coordinateSystem"]["wkt"].get<std::string>();
  INFO(wkt);
  CHECK(wkt.find("UTM zone 33N") != std::string::npos);
  CHECK(wkt.find("ID[\"EPSG\",32633]") != std::string::npos);
  const auto green = gdalXyz(f, 2);
  REQUIRE(green.size() == 8);
  CHECK(green[5][0] == doctest::Approx(500000.1));
  CHECK(green[5][1] == doctest::Approx(4649775.9));
  CHECK(green[5][2] == 10 * (3 * 5 + 1));
}

TEST_CASE("GeoTIFF: the dataset's own frame reads as a local metric frame, and bad grids are refused") {
  TempDir dir;
  GeoGrid g;
  g.width = 2, g.height = 2, g.x0 = -1, g.yTop = 1, g.dx = 2, g.dy = 2;
  const fs::path f = dir.path / "local.tif";
  writeGeoTiffFloat(f.string(), g, {{"water depth", "m"}}, {1, 2, 3, 4});
  // gdalinfo -json says it cannot place a local frame's corners on the WGS 84 ellipsoid: right, it has no place on Earth
  const nlohmann::json info = gdalInfo(f, "proj_get_ellipsoid");
  const std::string wkt = info["coordinateSystem"]["wkt"].get<std::string>();
  INFO(wkt);
  const bool local = wkt.find("LOCAL_CS") != std::string::npos || wkt.find("ENGCRS") != std::string::npos;
  CHECK(local);
  CHECK(wkt.find("metre") != std::string::npos);
  CHECK(wkt.find("Refrax dataset frame") != std::string::npos);
  CHECK_THROWS_WITH_AS(writeGeoTiffFloat((dir.path / "a.tif").string(), g, {{"x", ""}}, {1, 2, 3}), doctest::Contains("not width x height"), Error);
  GeoGrid flat = g;
  flat.dy = 0;
  CHECK_THROWS_WITH_AS(writeGeoTiffFloat((dir.path / "b.tif").string(), flat, {{"x", ""}}, {1, 2, 3, 4}), doctest::Contains("spacing"), Error);
  CHECK(!fs::exists(dir.path / "a.tif"));
  CHECK(!fs::exists(dir.path / "b.tif"));
}
