// refrax-view in a real window under Xvfb: its render must equal the headless render of the
// same camera, and without a display it must stop with one clear error.
#ifdef REFRAX_VIEWER
#include <doctest/doctest.h>

#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <algorithm>
#include <sys/wait.h>

#include "engine/io/image_io.h"
#include "engine/surface/builtin_surfaces.h"
#include "engine/surface/grid_mesh.h"
#include "engine/surface/gltf_surface.h"
#include "engine/train/checkpoint.h"
#include "engine/train/train_run.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {
test::CliResult runShell(const std::string& command) {
  // runCli prefixes the refrax binary; this runs any command line the same way
  std::string cmd = command + " 2>&1";
  test::CliResult r{-1, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while (p && (n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  if (p) {
    int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return r;
}

double maxDifference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) return 1e9;
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); i++) m = std::max(m, double(std::fabs(a.pixels[i] - b.pixels[i])));
  return m;
}

// Fraction of pixels with a channel more than `above` apart.
double fractionDiffering(const Image& a, const Image& b, double above) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) return 1;
  size_t n = 0;
  for (size_t p = 0; p < a.pixels.size() / 3; p++) {
    bool differs = false;
    for (int c = 0; c < 3; c++) differs = differs || std::fabs(a.pixels[3 * p + c] - b.pixels[3 * p + c]) > above;
    n += differs;
  }
  return double(n) / double(a.pixels.size() / 3);
}

// A tiny run trained once per test process: 20 steps, checkpoints at 10 and 20 (face normals
// until step 10, interpolated after: both surface modes are seen).
const std::string& viewerRun() {
  static test::TrainTempDir dir;
  static std::string run;
  if (run.empty()) {
    std::string data = test::tinyDataset("nerfrac-primary-sine");
    test::CliResult r = test::runCli("train " + data + " -o " + (dir / "run") +
                                     " --steps 20 --gaussians 300 --patch 16 --checkpoint-every 10 --progress-every 100");
    REQUIRE_MESSAGE(r.exitCode == 0, r.output);
    run = dir / "run";
  }
  return run;
}

std::string viewer(const std::string& options) {
  return std::string("REFRAX_VALIDATION=1 xvfb-run -a ") + REFRAX_VIEWER + " " + options;
}
}  // namespace

TEST_CASE("refrax-view under Xvfb renders what refrax preview renders for the same camera") {
  fs::path dir = fs::temp_directory_path() / ("refrax-view-" + std::to_string(test::freshSeed()));
  fs::create_directories(dir);
  std::string shot = (dir / "view.png").string(), ref = (dir / "preview.png").string(), other = (dir / "other.png").string();
  std::string camera = " --camera 0.3,-1.8,1.2,0,0.1,0 --surface triangle --mode wireframe --width 256 --height 192";
  auto v = runShell(std::string("REFRAX_VALIDATION=1 xvfb-run -a ") + REFRAX_VIEWER + " --frames 3 --screenshot " + shot + camera);
  INFO(v.output);
  REQUIRE(v.exitCode == 0);
  CHECK(v.output.find("validation messages: 0") != std::string::npos);
  REQUIRE(test::runCli("preview -o " + ref + camera).exitCode == 0);
  REQUIRE(test::runCli("preview -o " + other + " --camera 0.3,-1.8,1.2,0,0.1,0 --surface sine --width 256 --height 192").exitCode == 0);
  Image a = readPng(shot), b = readPng(ref), c = readPng(other);
  CHECK(maxDifference(a, b) <= 1.0 / 255.0);  // same shader, same inputs: equal up to rounding
  CHECK(maxDifference(a, c) > 0.1);           // and the comparison can tell surfaces apart
  fs::remove_all(dir);
}

// With --exact-water the viewer traces the same rays through the same stages as `refrax
// render --exact-water` (camera rays, the subdivided proxy surface, the Gaussian forward, round-half-up to 8
// bits): for a dataset camera (same intrinsics, double precision) the PNGs are equal; measured
// 0 of 4096 pixels differing. Allowed: 1/255 (a float rounding exactly at .5).
TEST_CASE("refrax-view shows a trained run's dataset camera as refrax render does, water kept, removed and swapped") {
  const std::string& run = viewerRun();
  test::TrainTempDir dir;
  std::map<std::string, Image> shots;
  for (std::string water : {"keep", "remove", "sine:0:0.05:0.5:30"}) {
    std::string shot = dir / ("view-" + std::to_string(shots.size()) + ".png"), out = dir / ("render-" + std::to_string(shots.size()));
    auto v = runShell(viewer(run + " --view test:0 --size 64 --frames 3 --exact-water --water " + water + " --screenshot " + shot));
    INFO(water << "\n" << v.output);
    REQUIRE(v.exitCode == 0);
    CHECK(v.output.find("validation messages: 0") != std::string::npos);
    CHECK(v.output.find("loaded step 20") != std::string::npos);
    auto r = test::runCli("render " + run + " -o " + out + " --split test --exact-water --water " + water);
    REQUIRE(r.exitCode == 0);
    Image a = readPng(shot), b = readPng(out + "/test_000.png");
    CHECK(maxDifference(a, b) <= 1.0 / 255.0);
    shots[water] = a;
    if (water == "keep") {
      // the viewer's default Gaussian trace is tiled (engine/gaussian/tiled_trace.h); the BVH traversal
      // per ray, as refrax render traces, gives the same image
      std::string bvhShot = dir / "view-bvh.png";
      auto w = runShell(viewer(run + " --view test:0 --size 64 --frames 3 --exact-water --gaussian-trace bvh --screenshot " + bvhShot));
      INFO(w.output);
      REQUIRE(w.exitCode == 0);
      CHECK(w.output.find("validation messages: 0") != std::string::npos);
      CHECK(maxDifference(readPng(bvhShot), b) <= 1.0 / 255.0);
      // Without --view the viewer opens at the first test camera (it opened at a free camera
      // outside the rig, where a trained scene is all floaters): the same image.
      std::string defaultShot = dir / "view-default.png";
      auto d = runShell(viewer(run + " --size 64 --frames 3 --exact-water --screenshot " + defaultShot));
      INFO(d.output);
      REQUIRE(d.exitCode == 0);
      CHECK(maxDifference(readPng(defaultShot), b) <= 1.0 / 255.0);
    }
  }
  // and the comparison can tell the water modes apart (20 steps leave a dim scene: measured
  // 15/255 and 16/255 apart, against the 1/255 allowed above)
  CHECK(maxDifference(shots["keep"], shots["remove"]) > 8.0 / 255.0);
  CHECK(maxDifference(shots["keep"], shots["sine:0:0.05:0.5:30"]) > 8.0 / 255.0);
}

// The viewer's fast path: the learned height field baked once into a mesh on the trainer's
// finest lattice (grid cells << subdivision levels), traced with one ray query per ray and
// flat triangles with area-weighted vertex normals, where the trainer's surface subdivides and
// Phong-interpolates its lattice normals. Measured against `refrax render --exact-water`: 46 of 4096 pixels
// differing, by at most 2/255 (20 steps) and 8/255 (300 steps), mean 0.01/255. Allowed: 3% of
// the pixels more than 1/255 apart, none more than 24/255. `refrax render` itself draws the baked frame.
// A triangle wave or a glTF mesh goes through cmdRefractThroughMesh in both programs: the
// viewer's triangle grid written as glTF and swapped in by `refrax render` gives the same PNG.
TEST_CASE("refrax-view's baked water and mesh swaps match refrax render") {
  const std::string& run = viewerRun();
  test::TrainTempDir dir;
  auto v = runShell(viewer(run + " --view test:0 --size 64 --frames 2 --screenshot " + (dir / "baked.png")));
  INFO(v.output);
  REQUIRE(v.exitCode == 0);
  CHECK(v.output.find("validation messages: 0") != std::string::npos);
  // Without --view or --camera a run opens at its first test camera (not a free camera
  // outside the rig, where a trained scene is all floaters).
  auto home = runShell(viewer(run + " --size 64 --frames 2 --screenshot " + (dir / "home.png")));
  INFO(home.output);
  REQUIRE(home.exitCode == 0);
  CHECK(maxDifference(readPng(dir / "home.png"), readPng(dir / "baked.png")) == 0.0);
  // refrax render draws the viewer's frame: the same baked water, one submission a frame.
  // --benchmark: the frame time, where it goes, and the Gaussian trace alone for the same rays.
  const test::CliResult bakedRender = test::runCli("render " + run + " -o " + (dir / "render") + " --split test --benchmark 2");
  INFO(bakedRender.output);
  REQUIRE(bakedRender.exitCode == 0);
  CHECK(maxDifference(readPng(dir / "render/test_000.png"), readPng(dir / "baked.png")) <= 1.0 / 255.0);
  CHECK(bakedRender.output.find("water keep (baked)") != std::string::npos);
  CHECK(bakedRender.output.find("benchmark: per frame (ms): rays ") != std::string::npos);
  for (const char* stage : {", water ", ", cull ", ", gaussians ", ", compose ", ", image readback ", ", image (host) "})
    CHECK_MESSAGE(bakedRender.output.find(stage) != std::string::npos, stage);
  CHECK(bakedRender.output.find("; 1 submission a frame") != std::string::npos);
  const size_t alone = bakedRender.output.find("benchmark: the Gaussian trace alone ");
  REQUIRE(alone != std::string::npos);
  const std::string ratioText = bakedRender.output.substr(bakedRender.output.find("the frame ", alone) + 10);
  const double ratio = std::stod(ratioText);
  CHECK(ratio > 0.5);  // a frame holds its trace (timing noise aside)
  CHECK(ratio < 50);
  // --exact-water: the trainer's subdivided surface, its trace before the frame's submission.
  const test::CliResult exactRender = test::runCli("render " + run + " -o " + (dir / "exact") + " --split test --exact-water --benchmark 1");
  INFO(exactRender.output);
  REQUIRE(exactRender.exitCode == 0);
  CHECK(exactRender.output.find("water keep (exact)") != std::string::npos);
  CHECK(exactRender.output.find("benchmark: per frame (ms): surface ") != std::string::npos);
  REQUIRE(test::runCli("render " + run + " -o " + (dir / "removed") + " --split test --water remove").exitCode == 0);
  Image baked = readPng(dir / "baked.png"), exact = readPng(dir / "exact/test_000.png"), removed = readPng(dir / "removed/test_000.png");
  CHECK(fractionDiffering(baked, exact, 1.5 / 255.0) <= 0.03);
  CHECK(maxDifference(baked, exact) <= 24.0 / 255.0);
  CHECK(fractionDiffering(baked, removed, 1.5 / 255.0) > 0.3);  // the water is there

  TrainConfig config = readRunConfig(run);
  const uint32_t cells = config.gridCells << config.subdivisionLevels;
  BuiltinSurface tri{"triangle", float(config.waterHeight), 0.05f, 0.5f, 30.0f};
  writeSurfaceGltf(dir / "tri.gltf", surfaceMeshFromGrid(makeGridMesh(cells, cells, float(config.domain.xMin), float(config.domain.yMin),
                                                                     float(config.domain.xMax), float(config.domain.yMax),
                                                                     surfaceHeightFunction(tri))));
  REQUIRE(test::runCli("render " + run + " -o " + (dir / "tri") + " --split test --water " + (dir / "tri.gltf")).exitCode == 0);
  Image reference = readPng(dir / "tri/test_000.png");
  for (std::string water : {std::string("triangle:") + std::to_string(config.waterHeight) + ":0.05:0.5:30", dir / "tri.gltf"}) {
    auto t = runShell(viewer(run + " --view test:0 --size 64 --frames 2 --water " + water + " --screenshot " + (dir / "swap.png")));
    INFO(water << "\n" << t.output);
    REQUIRE(t.exitCode == 0);
    CHECK(t.output.find("validation messages: 0") != std::string::npos);
    Image swapped = readPng(dir / "swap.png");
    CHECK(maxDifference(swapped, reference) <= 1.0 / 255.0);
    CHECK(fractionDiffering(swapped, baked, 1.5 / 255.0) > 0.1);  // not the learned water
  }
}

// A look-at camera goes through the fly camera's float yaw and pitch, so its rays differ from
// `refrax render --camera`'s double-precision look-at in the last bits: measured 1/255 at 1 to
// 3 of 7680 pixels. Allowed: 1% of the pixels more than 1/255 apart (a ray grazing a Gaussian's
// cut-off can change one pixel more).
TEST_CASE("refrax-view of a run's PLY with a look-at camera matches refrax render with the water removed") {
  const std::string& run = viewerRun();
  test::TrainTempDir dir;
  std::string camera = " --camera 0.2,-0.9,0.6,0,0,-0.6 --fov 45 --width 96 --height 80";
  auto v = runShell(viewer("--ply " + run + "/point_cloud.ply --frames 2 --screenshot " + (dir / "ply.png") + camera));
  INFO(v.output);
  REQUIRE(v.exitCode == 0);
  CHECK(v.output.find("validation messages: 0") != std::string::npos);
  REQUIRE(test::runCli("render " + run + " -o " + (dir / "render") + " --water remove" + camera).exitCode == 0);
  REQUIRE(test::runCli("render " + run + " -o " + (dir / "kept") + camera).exitCode == 0);
  Image a = readPng(dir / "ply.png"), b = readPng(dir / "render/camera.png"), c = readPng(dir / "kept/camera.png");
  CHECK(fractionDiffering(a, b, 1.5 / 255.0) <= 0.01);
  CHECK(fractionDiffering(a, c, 1.5 / 255.0) > 0.2);  // a PLY has no water: it is not the kept view
}

// A run being trained: the viewer loads the newest checkpoint, and a newer one that appears
// while it runs (moved in atomically, as the trainer writes them) within its 1 s poll.
TEST_CASE("refrax-view follows a run and loads a newer checkpoint when it appears") {
  test::TrainTempDir dir;
  std::string run = dir / "run";
  fs::copy(viewerRun(), run, fs::copy_options::recursive);
  std::string newer = checkpointPath(run, 20), aside = dir / "step20.ckpt";
  fs::rename(newer, aside);
  std::string shot = dir / "view.png";
  // 40 frames can pass in under a second once the pipelines are cached: --min-seconds makes
  // the viewer outlast its 1 s checkpoint poll however fast the device is.
  std::string cmd = viewer(run + " --view test:0 --size 64 --frames 40 --min-seconds 4 --exact-water --screenshot " + shot) + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::string output;
  char line[4096];
  bool moved = false;
  while (fgets(line, sizeof line, p)) {
    output += line;
    if (!moved && std::string(line).find("loaded step 10") != std::string::npos) {
      fs::rename(aside, newer);
      moved = true;
    }
  }
  int status = pclose(p);
  INFO(output);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(moved);
  CHECK(output.find("loaded step 20") != std::string::npos);
  CHECK(output.find("validation messages: 0") != std::string::npos);
  REQUIRE(test::runCli("render " + run + " -o " + (dir / "render") + " --split test --exact-water").exitCode == 0);
  CHECK(maxDifference(readPng(shot), readPng(dir / "render/test_000.png")) <= 1.0 / 255.0);

  // --min-seconds is checked before any window opens.
  for (const char* bad : {" --frames 2 --min-seconds -1", " --frames 2 --min-seconds nan", " --min-seconds 2"}) {
    auto r = runShell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + REFRAX_VIEWER + " " + run + bad);
    INFO(bad << "\n" << r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("--min-seconds") != std::string::npos);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
  }
}

// --auto-resolution: a frame rate no device holds at 256 x 256 (1,000 FPS on lavapipe, or on a
// GPU through the 20% per frame the scale may move) shrinks the render; off (the default with
// --frames), the render keeps the window's size.
TEST_CASE("refrax-view's automatic resolution lowers the render's size to hold a frame rate") {
  const std::string& run = viewerRun();
  auto fixed = runShell(viewer(run + " --size 256 --frames 12"));
  INFO(fixed.output);
  REQUIRE(fixed.exitCode == 0);
  CHECK(fixed.output.find("rendered 12 frames at 256x256") != std::string::npos);
  auto scaled = runShell(viewer(run + " --size 256 --frames 12 --auto-resolution on --target-fps 1000"));
  INFO(scaled.output);
  REQUIRE(scaled.exitCode == 0);
  const size_t at = scaled.output.find("rendered 12 frames at ");
  REQUIRE(at != std::string::npos);
  const int width = std::stoi(scaled.output.substr(at + 22));
  CHECK(width < 256);
  CHECK(width >= 25);  // the scale's floor, 0.1
}

TEST_CASE("refrax-view with a missing run or a bad PLY stops with one clear error") {
  test::TrainTempDir dir;
  std::ofstream(dir / "bad.ply") << "not a ply\n";
  fs::create_directories(dir / "empty");
  struct Case {
    std::string args, message;
  } cases[] = {{"/no/such/run", "is not a training run"},
               {dir / "empty", "is not a training run"},
               {"--ply " + (dir / "bad.ply"), "is not a PLY file"},
               {"--ply /no/such.ply", "cannot open Gaussian PLY"},
               {"/no/such/run --ply /no/such.ply", "not both"},
               {"--gaussian-trace rays", "--gaussian-trace must be tiles or bvh"},
               {"--size 0", "--size must be between 1 and 8192"},
               {"--auto-resolution maybe", "--auto-resolution must be on or off"},
               {"--target-fps 0", "--target-fps must be between 1 and 1000"},
               {"--bogus", "unknown option --bogus for 'refrax-view'"}};
  for (const auto& c : cases) {
    // checked before any window opens: the same error with or without a display
    auto r = runShell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + REFRAX_VIEWER + " " + c.args + " --frames 1");
    INFO(c.args << "\n" << r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("refrax-view: error: ") == 0);
    CHECK(r.output.find(c.message) != std::string::npos);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
  }
}

TEST_CASE("refrax-view without a display stops with one clear error") {
  auto r = runShell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + REFRAX_VIEWER + " --frames 1");
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("refrax-view: error: no display") != std::string::npos);
}

TEST_CASE("refrax preview rejects bad arguments with one error") {
  CHECK(test::runCli("preview").exitCode == 1);
  CHECK(test::runCli("preview -o /tmp/x.png --surface lake").output.find("unknown surface 'lake'") != std::string::npos);
  CHECK(test::runCli("preview -o /tmp/x.png --camera 1,2").output.find("must be x,y,z") != std::string::npos);
  CHECK(test::runCli("preview -o /no/such/dir/x.png").exitCode == 1);
}
#endif
