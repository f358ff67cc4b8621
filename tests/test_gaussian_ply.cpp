// Gaussians in the 3DGS PLY layout: bitwise round trip, the standard property order, lower
// SH degrees, and one clear error for missing properties, truncation and NaN.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/gaussian/ply_gaussians.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

std::string tempPath(const std::string& name) { return "/tmp/refrax_test_" + std::to_string(::getpid()) + "_" + name; }

// A PLY written by hand: `names` float properties, `rows` of values.
void writeRawPly(const std::string& path, const std::vector<std::string>& names, const std::vector<float>& values, size_t declaredCount) {
  std::string h = "ply\nformat binary_little_endian 1.0\ncomment by hand\nelement vertex " + std::to_string(declaredCount) + "\n";
  for (auto& n : names) h += "property float " + n + "\n";
  h += "end_header\n";
  h.append(reinterpret_cast<const char*>(values.data()), values.size() * 4);
  writeFileAtomic(path, h.data(), h.size());
}

std::vector<std::string> standardNames(int restCount = 45) {
  std::vector<std::string> n = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  for (int i = 0; i < restCount; i++) n.push_back("f_rest_" + std::to_string(i));
  n.push_back("opacity");
  for (int i = 0; i < 3; i++) n.push_back("scale_" + std::to_string(i));
  for (int i = 0; i < 4; i++) n.push_back("rot_" + std::to_string(i));
  return n;
}

}  // namespace

TEST_CASE("Gaussian PLY round trip is bitwise and uses the 3DGS property order") {
  std::mt19937 rng(refrax::test::freshSeed());
  GaussianSet set = randomGaussians(rng, 257);
  // awkward values survive too
  set.at(0)[0] = -0.0f;
  set.at(1)[20] = 1e-38f;
  set.at(2)[f32::kGaussLogitDensity] = -88.0f;
  std::string path = tempPath("roundtrip.ply");
  writeGaussiansPly(path, set);
  GaussianSet back = readGaussiansPly(path);
  REQUIRE(back.params.size() == set.params.size());
  CHECK(std::memcmp(back.params.data(), set.params.data(), set.params.size() * 4) == 0);
  std::string first = readFile(path);
  writeGaussiansPly(path, back);
  CHECK(readFile(path) == first);
  // the layout: header names in order, then rows of 62 floats; f_rest channel-major
  auto names = standardNames();
  std::string header = first.substr(0, first.find("end_header\n") + 11);
  size_t pos = 0;
  for (auto& n : names) {
    pos = header.find("property float " + n + "\n", pos);
    REQUIRE(pos != std::string::npos);
  }
  REQUIRE(first.size() == header.size() + set.count() * names.size() * 4);
  const float* row = reinterpret_cast<const float*>(first.data() + header.size()) + 5 * names.size();  // Gaussian 5
  const float* g = set.at(5);
  CHECK(row[0] == g[f32::kGaussMean]);
  CHECK(row[6 + 1] == g[f32::kGaussSH + 1]);               // f_dc_1: green DC
  CHECK(row[9 + 0] == g[f32::kGaussSH + 3 * 1 + 0]);       // f_rest_0: red, coefficient 1
  CHECK(row[9 + 15] == g[f32::kGaussSH + 3 * 1 + 1]);      // f_rest_15: green, coefficient 1
  CHECK(row[9 + 44] == g[f32::kGaussSH + 3 * 15 + 2]);     // f_rest_44: blue, coefficient 15
  CHECK(row[54] == g[f32::kGaussLogitDensity]);             // opacity
  CHECK(row[58] == g[f32::kGaussRotation]);                 // rot_0 = w
  std::remove(path.c_str());
}

TEST_CASE("Gaussian PLY of SH degree 1 reads with zero higher coefficients") {
  auto names = standardNames(9);
  std::vector<float> values(2 * names.size());
  for (size_t i = 0; i < values.size(); i++) values[i] = float(i % names.size()) + 0.5f;
  std::string path = tempPath("degree1.ply");
  writeRawPly(path, names, values, 2);
  GaussianSet set = readGaussiansPly(path);
  REQUIRE(set.count() == 2);
  CHECK(set.at(1)[f32::kGaussSH + 3 * 1 + 0] == 9.5f);   // f_rest_0 -> red coefficient 1
  CHECK(set.at(1)[f32::kGaussSH + 3 * 1 + 1] == 12.5f);  // f_rest_3 -> green coefficient 1
  CHECK(set.at(1)[f32::kGaussSH + 3 * 4 + 0] == 0.0f);   // degree 2 absent
  std::remove(path.c_str());
}

TEST_CASE("a bad Gaussian PLY gives one clear error") {
  auto names = standardNames();
  std::vector<float> values(3 * names.size(), 0.25f);
  std::string path = tempPath("bad.ply");

  auto missing = names;
  missing.erase(missing.end() - 1);  // no rot_3
  writeRawPly(path, missing, std::vector<float>(3 * missing.size(), 0.25f), 3);
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("lacks the property 'rot_3'"), Error);

  writeRawPly(path, names, std::vector<float>(values.begin(), values.end() - 7), 3);  // last row cut short
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("truncated"), Error);

  auto withNan = values;
  withNan[names.size() + 2] = std::nanf("");
  writeRawPly(path, names, withNan, 3);
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("non-finite"), Error);

  std::string text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n";
  writeFileAtomic(path, text.data(), text.size());
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("binary_little_endian"), Error);

  writeFileAtomic(path, "not a ply", 9);
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("not a PLY"), Error);
  std::remove(path.c_str());
  CHECK_THROWS_WITH_AS(readGaussiansPly(path), doctest::Contains("cannot open"), Error);

  GaussianSet nanSet;
  nanSet.params.assign(kGaussianFloats, 0.1f);
  nanSet.params[3] = 1.0f;
  nanSet.params[30] = std::nanf("");
  CHECK_THROWS_WITH_AS(writeGaussiansPly(path, nanSet), doctest::Contains("non-finite"), Error);
  std::ifstream none(path);
  CHECK_FALSE(none.good());  // nothing written
}

TEST_CASE("refrax render-gaussians renders a PLY without the water and refuses a bad one") {
  std::mt19937 rng(refrax::test::freshSeed());
  RandomGaussianOptions o;
  o.sigmaMin = 0.03f, o.sigmaMax = 0.08f;
  GaussianSet set = randomGaussians(rng, 300, o);
  std::string ply = tempPath("render.ply"), png = tempPath("render.png");
  writeGaussiansPly(ply, set);
  auto r = refrax::test::runCli("render-gaussians " + ply + " --out " + png + " --width 40 --height 30 --background 0,0,1");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  Image img = readPng(png);
  REQUIRE(img.width == 40);
  REQUIRE(img.height == 30);
  int background = 0, scene = 0;
  for (int y = 0; y < img.height; y++)
    for (int x = 0; x < img.width; x++) {
      bool bg = img.at(x, y, 0) == 0.0f && img.at(x, y, 1) == 0.0f && img.at(x, y, 2) == 1.0f;
      background += bg;
      scene += !bg;
    }
  CHECK(scene > 100);  // the Gaussians show, and
  CHECK(background > 0);  // the blue background around them
  auto bad = refrax::test::runCli("render-gaussians " + tempPath("missing.ply") + " --out " + png);
  CHECK(bad.exitCode != 0);
  CHECK(bad.output.find("cannot open Gaussian PLY") != std::string::npos);
  std::remove(ply.c_str());
  std::remove(png.c_str());
}
