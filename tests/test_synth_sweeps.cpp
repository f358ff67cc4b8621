// refrax synth's sweep options: --tilt (the NeRFrac-like rig turned from the vertical about
// the pool-floor centre, for camera-tilt sweeps), --rig-spacing (that rig's baseline, for
// baseline sweeps) and --ior (the water's IOR, for IOR sweeps).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/synth/synth_presets.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;
using namespace refrax::synth;
namespace fs = std::filesystem;

namespace {

// The project's temporary folder (tests/train_test_util.h), removed at scope exit.
using TempDir = test::TrainTempDir;

using test::textureDir;

double degreesFromVertical(const glm::dvec3& axis) { return std::acos(glm::normalize(axis).z) * 180 / M_PI; }

// Distance from `p` to the camera's view axis (the ray along -Z from its centre).
double distanceToViewAxis(const SynthCamera& c, const glm::dvec3& p) {
  glm::dvec3 o = cameraCentre(c), d = -glm::normalize(glm::dvec3(c.cameraToWorld[2]));
  glm::dvec3 v = p - o;
  return glm::length(v - glm::dot(v, d) * d);
}

std::vector<std::string> filesUnder(const fs::path& root) {
  std::vector<std::string> files;
  for (auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root).string());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST_CASE("synth: --tilt turns the whole NeRFrac-like rig DEG from the vertical, every camera still seeing the pool-floor centre") {
  std::mt19937 rng(test::freshSeed());
  double tilt = std::uniform_real_distribution<double>(5, 60)(rng);
  INFO("tilt " << tilt);
  SynthPreset base = makeSynthPreset("nerfrac-primary-sine", SynthSize::Tiny, 1, textureDir());
  SynthPreset tilted = base;
  SynthVariation v;
  v.tiltDeg = tilt;
  applySynthVariation(tilted, v);
  REQUIRE(tilted.train.size() == 8);
  REQUIRE(tilted.test.size() == 1);
  const glm::dvec3 pivot = base.rigPivot;
  CHECK(pivot == glm::dvec3(0, 0, -0.5));
  std::vector<SynthCamera> all = tilted.train;
  all.insert(all.end(), tilted.test.begin(), tilted.test.end());
  std::vector<SynthCamera> before = base.train;
  before.insert(before.end(), base.test.begin(), base.test.end());
  for (size_t i = 0; i < all.size(); i++) {
    const SynthCamera& c = all[i];
    // Axes orthonormal, the view axis (back = +Z column) tilt degrees from the vertical.
    glm::dmat3 r(c.cameraToWorld);
    glm::dmat3 rtr = glm::transpose(r) * r;
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) CHECK(rtr[a][b] == doctest::Approx(a == b ? 1.0 : 0.0).epsilon(1e-12));
    CHECK(degreesFromVertical(glm::dvec3(c.cameraToWorld[2])) == doctest::Approx(tilt).epsilon(1e-9));
    // A rigid turn about the pivot: distances to it kept, the camera now on the -y side above the water.
    CHECK(glm::length(cameraCentre(c) - pivot) == doctest::Approx(glm::length(cameraCentre(before[i]) - pivot)).epsilon(1e-12));
    CHECK(cameraCentre(c).z > tilted.water.meanHeight + waveHeightBound(tilted.water));
    // The pool-floor centre in front of the camera and inside its image.
    glm::dvec3 local = glm::inverse(c.cameraToWorld) * glm::dvec4(pivot, 1.0);
    REQUIRE(local.z < 0);
    double px = c.cx + c.fx * local.x / -local.z, py = c.cy - c.fy * local.y / -local.z;
    CHECK(px > 0);
    CHECK(px < c.width);
    CHECK(py > 0);
    CHECK(py < c.height);
    // Intrinsics untouched.
    CHECK(c.fx == before[i].fx);
    CHECK(c.width == before[i].width);
  }
  // The centre camera looks exactly at the pivot; the outer ones keep their 0.2 rig offset.
  CHECK(distanceToViewAxis(tilted.test[0], pivot) < 1e-12);
  for (const auto& c : tilted.train) CHECK(distanceToViewAxis(c, pivot) <= 0.2 * std::sqrt(2.0) + 1e-12);
  // The camera moved towards -y and looks towards +y.
  CHECK(cameraCentre(tilted.test[0]).y < 0);
  CHECK(glm::dvec3(tilted.test[0].cameraToWorld[2]).y < 0);
  // The water-removal view follows the test view.
  CHECK(tilted.air[0].cameraToWorld == tilted.test[0].cameraToWorld);

  // Tilt 0 is the preset itself.
  SynthPreset zero = base;
  applySynthVariation(zero, SynthVariation{});
  for (size_t i = 0; i < zero.train.size(); i++) CHECK(zero.train[i].cameraToWorld == base.train[i].cameraToWorld);
}

TEST_CASE("synth: --rig-spacing moves the NeRFrac-like rig's cameras M apart, heights, view axes and intrinsics kept, before --tilt") {
  std::mt19937 rng(test::freshSeed());
  const double spacing = std::uniform_real_distribution<double>(0.05, 0.6)(rng);
  INFO("spacing " << spacing);
  SynthPreset base = makeSynthPreset("nerfrac-hybrid", SynthSize::Tiny, 1, textureDir());
  CHECK(base.rigSpacing == 0.2);
  SynthPreset wide = base;
  SynthVariation v;
  v.rigSpacing = spacing;
  applySynthVariation(wide, v);
  CHECK(wide.rigSpacing == spacing);
  CHECK(wide.description.find("rig spacing") != std::string::npos);
  REQUIRE(wide.train.size() == 8);
  // The grid again, row-major from (-x, +y) with the centre held out: the centre camera stays.
  const glm::dvec3 centre = cameraCentre(base.test[0]);
  CHECK(cameraCentre(wide.test[0]) == centre);
  CHECK(wide.air[0].cameraToWorld == wide.test[0].cameraToWorld);
  for (size_t i = 0; i < wide.train.size(); i++) {
    const int cell = int(i < 4 ? i : i + 1), col = cell % 3, row = cell / 3;
    const glm::dvec3 o = cameraCentre(wide.train[i]);
    CHECK(o.x == doctest::Approx(centre.x + (col - 1) * spacing).epsilon(1e-12));
    CHECK(o.y == doctest::Approx(centre.y + (1 - row) * spacing).epsilon(1e-12));
    CHECK(o.z == cameraCentre(base.train[i]).z);
    for (int a = 0; a < 3; a++) CHECK(glm::dvec3(wide.train[i].cameraToWorld[a]) == glm::dvec3(base.train[i].cameraToWorld[a]));
    CHECK(wide.train[i].fx == base.train[i].fx);
    CHECK(wide.train[i].cx == base.train[i].cx);
  }
  // With a tilt the spacing applies first: the turned rig keeps it between neighbours.
  SynthPreset both = base;
  v.tiltDeg = 20;
  applySynthVariation(both, v);
  CHECK(glm::length(cameraCentre(both.train[1]) - cameraCentre(both.train[0])) == doctest::Approx(spacing).epsilon(1e-12));
  CHECK(glm::length(cameraCentre(both.train[3]) - cameraCentre(both.train[0])) == doctest::Approx(spacing).epsilon(1e-12));
  CHECK(distanceToViewAxis(both.test[0], both.rigPivot) < 1e-12);
}

TEST_CASE("synth: --ior lands in water.json and changes the images, --tilt reaches the poses, the same seed stays byte-identical") {
  TempDir dir;
  const std::string common = "synth nerfrac-primary-sine --size tiny --width 24 --seed 4 ";
  for (const char* out : {"a", "b"}) {
    auto r = test::runCli(common + "--tilt 30 --ior 1.4 -o " + (dir / out));
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
  }
  auto plain = test::runCli(common + "-o " + (dir / "plain"));
  auto ior = test::runCli(common + "--ior 1.4 -o " + (dir / "ior"));
  INFO(plain.output << ior.output);
  REQUIRE(plain.exitCode == 0);
  REQUIRE(ior.exitCode == 0);

  auto files = filesUnder(dir.path / "a");
  CHECK(files == filesUnder(dir.path / "b"));
  for (const auto& f : files) CHECK_MESSAGE(readFile(dir / ("a/" + f)) == readFile(dir / ("b/" + f)), f);

  CHECK(readJson(dir / "plain/water.json")["ior"].get<double>() == doctest::Approx(1.1).epsilon(1e-12));
  CHECK(readJson(dir / "ior/water.json")["ior"].get<double>() == 1.4);
  CHECK(readJson(dir / "a/water.json")["ior"].get<double>() == 1.4);
  // Refraction bends more: every view through the water changes, the view without water does not.
  CHECK(readFile(dir / "plain/test/000.png") != readFile(dir / "ior/test/000.png"));
  CHECK(readFile(dir / "plain/train/000.png") != readFile(dir / "ior/train/000.png"));
  CHECK(readFile(dir / "plain/test_air/000.png") == readFile(dir / "ior/test_air/000.png"));
  // The poses written are the tilted ones.
  for (const char* split : {"transforms_train.json", "transforms_test.json"}) {
    nlohmann::json t = readJson(dir / (std::string("a/") + split));
    for (const auto& frame : t["frames"]) {
      const auto& m = frame["transform_matrix"];
      glm::dvec3 back(m[0][2].get<double>(), m[1][2].get<double>(), m[2][2].get<double>());
      CHECK(degreesFromVertical(back) == doctest::Approx(30).epsilon(1e-9));
    }
  }
  CHECK(readJson(dir / "plain/transforms_test.json")["frames"][0]["transform_matrix"][2][2].get<double>() == doctest::Approx(1.0));
}

TEST_CASE("synth: a bad --tilt, --rig-spacing or --ior is one clear error and leaves no output") {
  TempDir dir;
  const std::pair<const char*, const char*> cases[] = {
      {"nerfrac-hybrid --tilt 61", "tilt must be 0..60"},
      {"nerfrac-hybrid --tilt -5", "tilt must be 0..60"},
      {"nerfrac-hybrid --tilt nan", "tilt must be 0..60"},
      {"nerfrac-hybrid --tilt steep", "--tilt expects a number"},
      {"desk --tilt 20", "NeRFrac-like presets"},
      {"nerfrac-hybrid --rig-spacing 0", "rig spacing must be in (0, 0.6] m"},
      {"nerfrac-hybrid --rig-spacing 0.61", "rig spacing must be in (0, 0.6] m"},
      {"nerfrac-hybrid --rig-spacing inf", "rig spacing must be in (0, 0.6] m"},
      {"desk-topdown --rig-spacing 0.3", "NeRFrac-like presets"},
      {"nerfrac-hybrid --ior 1.0", "IOR must be greater than 1 and at most 2"},
      {"nerfrac-hybrid --ior 2.5", "IOR must be greater than 1 and at most 2"},
      {"desk --ior 0", "IOR must be greater than 1 and at most 2"},
  };
  for (const auto& [args, expect] : cases) {
    auto r = test::runCli(std::string("synth ") + args + " --size tiny -o " + (dir / "x"));
    INFO(args << ": " << r.output);
    CHECK(r.exitCode != 0);
    CHECK(r.output.find(expect) != std::string::npos);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    CHECK(!fs::exists(dir / "x"));
  }
  // Strong waves under a steep rig: a camera would sit between the crests.
  SynthPreset p = makeSynthPreset("nerfrac-primary-sine", SynthSize::Tiny, 1, textureDir());
  SynthVariation v;
  v.tiltDeg = 60;
  v.amplitudeScale = 3.2;  // crests at 0.08, above the low row's camera (0.077 after a 60 deg turn)
  CHECK_THROWS_WITH_AS(applySynthVariation(p, v), doctest::Contains("under the wave crests"), Error);
}

TEST_CASE("synth: a 3 x 3 rig holds four test views between its training cameras, each the centre of a 2 x 2 cell, spaced and tilted with the rig") {
  for (const char* name : {"nerfrac-primary-sine", "desk-topdown"}) {
    INFO(name);
    SynthPreset p = makeSynthPreset(name, SynthSize::Tiny, 1, textureDir());
    SynthVariation v;
    if (p.tiltableRig) v.rigSpacing = 0.3, v.tiltDeg = 20;
    applySynthVariation(p, v);
    REQUIRE(p.between.size() == 4);
    // The rig in row-major order with the centre (the test view) back in its cell.
    std::vector<SynthCamera> rig = p.train;
    rig.insert(rig.begin() + 4, p.test.front());
    for (size_t k = 0; k < 4; k++) {
      const size_t row = k / 2, col = k % 2;  // the cell whose corners are rig[(row + a) * 3 + col + b]
      glm::dvec3 mean(0);
      for (size_t a = 0; a < 2; a++)
        for (size_t b = 0; b < 2; b++) mean += cameraCentre(rig[(row + a) * 3 + col + b]) / 4.0;
      const glm::dvec3 o = cameraCentre(p.between[k]);
      for (int axis = 0; axis < 3; axis++) CHECK(o[axis] == doctest::Approx(mean[axis]).epsilon(1e-12));
      // Parallel to the rig, the same intrinsics.
      for (int a = 0; a < 3; a++) CHECK(glm::length(glm::dvec3(p.between[k].cameraToWorld[a]) - glm::dvec3(p.test[0].cameraToWorld[a])) < 1e-12);
      CHECK(p.between[k].fx == p.test[0].fx);
      CHECK(p.between[k].width == p.test[0].width);
    }
  }
  // The ring presets hold out six test views of their own and no between views.
  CHECK(makeSynthPreset("desk", SynthSize::Tiny, 1, textureDir()).between.empty());
}
