#pragma once
// GDAL (Debian's gdal-bin, scripts/install-deps.sh) reading our GeoTIFFs back, for the tests:
// gdalinfo's JSON report and gdal_translate's XYZ values.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/io/atomic_file.h"
#include "tests/gpu_test.h"

namespace refrax::test {

// gdalinfo's report; what it says on stderr (a warning about a malformed tag) fails the check,
// but for lines holding `expected`.
inline nlohmann::json gdalInfo(const std::filesystem::path& file, const std::string& expected = "") {
  const std::filesystem::path err = file.string() + ".stderr";
  CliResult r = runShell("{ gdalinfo -json " + file.string() + " 2>" + err.string() + "; }");
  std::string warnings;
  std::stringstream lines(std::filesystem::exists(err) ? readFile(err.string()) : "");
  for (std::string line; std::getline(lines, line);)
    if (expected.empty() || line.find(expected) == std::string::npos) warnings += line + "\n";
  std::filesystem::remove(err);
  INFO(r.output);
  INFO("gdalinfo's stderr: " << warnings);
  REQUIRE_MESSAGE(r.exitCode == 0, "gdalinfo (Debian's gdal-bin, scripts/install-deps.sh installs it) must read " << file);
  CHECK(warnings.empty());
  return nlohmann::json::parse(r.output);
}

// gdal_translate's XYZ of one band: "x y value" per pixel, at the pixel's centre as GDAL places it.
inline std::vector<std::array<double, 3>> gdalXyz(const std::filesystem::path& tif, int band) {
  const std::filesystem::path out = tif.string() + "." + std::to_string(band) + ".xyz";
  CliResult r = runShell("gdal_translate -q -of XYZ -b " + std::to_string(band) + " " + tif.string() + " " + out.string());
  INFO(r.output);
  REQUIRE_MESSAGE(r.exitCode == 0, "gdal_translate (Debian's gdal-bin) must read " << tif);
  std::stringstream in(readFile(out.string()));
  std::vector<std::array<double, 3>> v;
  std::string x, y, z;
  while (in >> x >> y >> z) v.push_back({std::stod(x), std::stod(y), z.find("nan") != std::string::npos ? NAN : std::stod(z)});
  std::filesystem::remove(out);
  return v;
}

}  // namespace refrax::test
