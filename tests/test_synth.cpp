// The synthetic data generator (refrax synth): its refraction against closed-form Snell
// geometry, its surface root finder against dense sampling, determinism, the LLFF pose
// convention, and clear errors on bad arguments.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <tiny_gltf.h>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/loss/metrics.h"
#include "engine/synth/bottom_truth.h"
#include "engine/synth/render_view.h"
#include "engine/synth/surface_intersect.h"
#include "engine/synth/synth_dataset.h"
#include "engine/synth/synth_presets.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"
#include "tests/water_json_height.h"

using namespace refrax;
using namespace refrax::synth;
namespace fs = std::filesystem;

namespace {

// The project's temporary folder (tests/train_test_util.h), removed at scope exit.
using TempDir = test::TrainTempDir;

// A plane at z = -depth under flat water, black except for a small white square centred on
// `marker`; the scene background is black too.
SynthScene markerScene(double depth, glm::dvec2 marker) {
  SynthScene scene;
  SynthTexture tex;
  tex.width = tex.height = 256;
  tex.rgb.assign(256 * 256 * 3, 0.0f);
  // Texels 126..129 (4 x 4) around the texture centre, which maps onto `marker` below.
  for (int y = 126; y < 130; y++)
    for (int x = 126; x < 130; x++)
      for (int c = 0; c < 3; c++) tex.rgb[(size_t(y) * 256 + x) * 3 + c] = 1.0f;
  scene.textures.push_back(tex);
  scene.materials.push_back({0, {1, 1}, {1, 1, 1}});
  SceneBuilder b;
  double h = 1.0;  // the plane spans 2 m, so a texel is 7.8 mm
  b.floorRect(marker.x - h, marker.y - h, marker.x + h, marker.y + h, -depth, 0);
  scene.bvh = buildTriangleBvh(std::move(b.triangles));
  scene.background = {0, 0, 0};
  return scene;
}

// Where the camera sees a point under flat water (z = 0, index n) by Snell's law: the
// refraction point P on the water splits the horizontal distance D into r1 (above) and
// r2 (below) with sin(atan(r1 / hc)) = n sin(atan(r2 / d)); then P is projected.
glm::dvec2 snellProjection(const SynthCamera& cam, const glm::dvec3& point, double n) {
  glm::dvec3 c = cameraCentre(cam);
  glm::dvec2 toPoint = glm::dvec2(point) - glm::dvec2(c);
  double D = glm::length(toPoint), hc = c.z, d = -point.z;
  double lo = 0, hi = D;
  for (int i = 0; i < 200; i++) {
    double r1 = 0.5 * (lo + hi);
    double g = std::sin(std::atan(r1 / hc)) - n * std::sin(std::atan((D - r1) / d));
    (g > 0 ? hi : lo) = r1;
  }
  glm::dvec2 p2 = glm::dvec2(c) + (D > 0 ? toPoint / D : glm::dvec2(0)) * lo;
  glm::dvec4 pc = glm::inverse(cam.cameraToWorld) * glm::dvec4(p2.x, p2.y, 0.0, 1.0);
  return {cam.cx + cam.fx * pc.x / -pc.z, cam.cy - cam.fy * pc.y / -pc.z};
}

glm::dvec2 directProjection(const SynthCamera& cam, const glm::dvec3& point) {
  glm::dvec4 pc = glm::inverse(cam.cameraToWorld) * glm::dvec4(point, 1.0);
  return {cam.cx + cam.fx * pc.x / -pc.z, cam.cy - cam.fy * pc.y / -pc.z};
}

glm::dvec2 brightCentroid(const RenderedView& v) {
  double sum = 0, sx = 0, sy = 0;
  for (int y = 0; y < v.height; y++)
    for (int x = 0; x < v.width; x++) {
      double w = v.rgb[(size_t(y) * v.width + x) * 3];
      sum += w;
      sx += w * (x + 0.5);
      sy += w * (y + 0.5);
    }
  REQUIRE(sum > 0);
  return {sx / sum, sy / sum};
}

void checkMarker(const SynthCamera& cam, double depth, glm::dvec2 marker, double ior) {
  SynthScene scene = markerScene(depth, marker);
  WaveSurface flat;
  flat.domain[0] = flat.domain[1] = -5;
  flat.domain[2] = flat.domain[3] = 5;
  RenderSettings settings;
  settings.samplesPerAxis = 4;
  RenderedView v = renderView(scene, &flat, ior, cam, settings, 7);
  glm::dvec3 m(marker.x, marker.y, -depth);
  glm::dvec2 seen = brightCentroid(v), expected = snellProjection(cam, m, ior), unrefracted = directProjection(cam, m);
  INFO("seen " << seen.x << "," << seen.y << " expected " << expected.x << "," << expected.y << " without water " << unrefracted.x << ","
               << unrefracted.y);
  // The check must be able to tell refraction from none.
  REQUIRE(glm::length(expected - unrefracted) > 3.0);
  CHECK(glm::length(seen - expected) < 0.5);
  // Every sample met the flat water.
  CHECK(v.samplesMissingWater == 0);
}

WaveSurface randomSurface(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0, 1);
  WaveSurface s;
  s.meanHeight = U(rng) - 0.5;
  s.domain[0] = s.domain[1] = -10;
  s.domain[2] = s.domain[3] = 10;
  int n = 2 + int(U(rng) * 6);
  for (int i = 0; i < n; i++) {
    double k = 2 * M_PI / (0.1 + 0.6 * U(rng)), a = 2 * M_PI * U(rng);
    s.waves.push_back({0.003 + 0.02 * U(rng), k * std::cos(a), k * std::sin(a), 2 * M_PI * U(rng)});
  }
  s.ripples.push_back({0.02 * U(rng), U(rng) - 0.5, U(rng) - 0.5, 2 * M_PI / (0.1 + 0.3 * U(rng)), 0.2 + 0.5 * U(rng)});
  return s;
}

std::vector<std::string> filesUnder(const fs::path& root) {
  std::vector<std::string> files;
  for (auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root).string());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST_CASE("synth: a marker under flat water appears where Snell refraction puts it (straight down and oblique)") {
  double ior = 1.33, depth = 0.4;
  glm::dvec2 marker(0.18, -0.12);
  // Straight down from 0.6 m above the water, the marker off-axis.
  checkMarker(downwardCamera({0, 0, 0.6}, 128, 128, 40 * M_PI / 180), depth, marker, ior);
  // Oblique: about 45 degrees from the vertical.
  checkMarker(lookAtCamera({-0.55, 0.3, 0.6}, {0.15, -0.1, -0.4}, {0, 0, 1}, 128, 128, 40 * M_PI / 180), depth, marker, ior);
  // NeRFrac's weaker index.
  checkMarker(lookAtCamera({0.6, 0.5, 0.7}, {0.1, -0.1, -0.4}, {0, 0, 1}, 128, 96, 45 * M_PI / 180), depth, marker, 1.1);
}

TEST_CASE("synth: the surface root finder finds the first crossing that dense sampling finds (grazing rays included)") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(0, 1);
  int hits = 0, grazingHits = 0, misses = 0;
  const int samples = 60000;
  for (int trial = 0; trial < 300; trial++) {
    WaveSurface s = randomSurface(rng);
    bool grazing = trial % 2 == 1;
    glm::dvec3 o, d;
    if (grazing) {
      // Start inside the wave band, travel almost horizontally (within ~1.5 degrees).
      o = {U(rng) - 0.5, U(rng) - 0.5, s.meanHeight + (U(rng) - 0.5) * waveHeightBound(s)};
      double a = 2 * M_PI * U(rng), dz = (U(rng) - 0.5) * 0.05;
      d = glm::normalize(glm::dvec3(std::cos(a), std::sin(a), dz));
      if (o.z <= waveHeight(s, o.x, o.y)) o.z = waveHeight(s, o.x, o.y) + 1e-4;  // start above the surface
    } else {
      o = {U(rng) - 0.5, U(rng) - 0.5, s.meanHeight + 0.2 + U(rng)};
      d = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, -0.05 - U(rng)));
    }
    const double tEnd = 3.0;
    auto f = [&](double t) { return o.z + t * d.z - waveHeight(s, o.x + t * d.x, o.y + t * d.y); };
    // Dense reference: the first sign change on a fine grid.
    double step = tEnd / samples, prev = f(0), tLo = -1;
    for (int i = 1; i <= samples; i++) {
      double cur = f(i * step);
      if ((cur > 0) != (prev > 0)) {
        tLo = (i - 1) * step;
        break;
      }
      prev = cur;
    }
    auto found = intersectWaveSurface(s, o, d, tEnd);
    INFO("trial " << trial << (grazing ? " (grazing)" : "") << " dense root in [" << tLo << ", " << tLo + step << "]");
    if (tLo < 0) {
      // Dense sampling saw no crossing; a reported one must be a real, earlier-than-grid pair.
      if (found) {
        CHECK(std::abs(f(found->t)) < 1e-9);
        CHECK(f(found->t - 1e-6) * f(found->t + 1e-6) < 0);
      }
      misses++;
      continue;
    }
    REQUIRE(found);
    CHECK(found->t >= tLo - 1e-9);
    CHECK(found->t <= tLo + step + 1e-9);
    CHECK(std::abs(f(found->t)) < 1e-9);
    CHECK(found->downward);
    hits++;
    grazingHits += grazing;
  }
  MESSAGE(hits << " hits (" << grazingHits << " grazing), " << misses << " misses");
  CHECK(grazingHits > 30);
  CHECK(misses > 0);
}

TEST_CASE("synth: the same seed gives byte-identical datasets and another seed a different one") {
  TempDir dir;
  for (const char* out : {"a", "b"}) {
    auto r = test::runCli("synth nerfrac-hybrid --size tiny --seed 5 -o " + (dir / out));
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
  }
  auto r = test::runCli("synth nerfrac-hybrid --size tiny --seed 6 -o " + (dir / "c"));
  REQUIRE(r.exitCode == 0);
  auto files = filesUnder(dir.path / "a");
  CHECK(files == filesUnder(dir.path / "b"));
  for (const char* expected : {"transforms_train.json", "transforms_test.json", "transforms_air.json", "water.json", "water_gt.gltf",
                               "water_gt_height.npy", "poses_bounds.npy", "images/000.png", "train/000.png", "test/000.png",
                               "test_air/000.png", "air/000.png", "masks/train_000.png", "masks/test_000.png"})
    CHECK_MESSAGE(std::find(files.begin(), files.end(), expected) != files.end(), expected);
  for (const auto& f : files) CHECK_MESSAGE(readFile(dir / ("a/" + f)) == readFile(dir / ("b/" + f)), f);
  CHECK(readFile(dir / "a/test/000.png") != readFile(dir / "c/test/000.png"));
  CHECK(readFile(dir / "a/water.json") != readFile(dir / "c/water.json"));
  // Nothing temporary is left beside the outputs.
  int entries = 0;
  for (auto& e : fs::directory_iterator(dir.path)) entries += 1 + 0 * e.is_directory();
  CHECK(entries == 3);
}

TEST_CASE("synth: --width and the wave scales vary a preset, bad values are one clear error") {
  TempDir dir;
  auto base = test::runCli("synth nerfrac-primary-sine --size tiny -o " + (dir / "a"));
  auto varied = test::runCli("synth nerfrac-primary-sine --size tiny --width 40 --wave-amplitude 2 --wavelength 0.8 -o " + (dir / "b"));
  INFO(base.output << varied.output);
  REQUIRE(base.exitCode == 0);
  REQUIRE(varied.exitCode == 0);
  auto a = readJson(dir / "a/water.json")["surface"]["directional_waves"][0], b = readJson(dir / "b/water.json")["surface"]["directional_waves"][0];
  CHECK(b["amplitude"].get<double>() == doctest::Approx(2 * a["amplitude"].get<double>()).epsilon(1e-12));
  CHECK(b["wavelength"].get<double>() == doctest::Approx(0.8 * a["wavelength"].get<double>()).epsilon(1e-12));
  CHECK(b["direction_deg"].get<double>() == doctest::Approx(a["direction_deg"].get<double>()).epsilon(1e-12));
  CHECK(b["phase"].get<double>() == a["phase"].get<double>());
  auto ta = readJson(dir / "a/transforms_train.json"), tb = readJson(dir / "b/transforms_train.json");
  CHECK(tb["w"].get<int>() == 40);
  CHECK(tb["h"].get<int>() == 40);
  CHECK(tb["camera_angle_x"].get<double>() == doctest::Approx(ta["camera_angle_x"].get<double>()).epsilon(1e-12));
  CHECK(readPng(dir / "b/train/000.png").width == 40);
  // The ground-truth height map follows the scaled waves.
  NpyArray ha = readNpy(dir / "a/water_gt_height.npy"), hb = readNpy(dir / "b/water_gt_height.npy");
  double ma = 0, mb = 0;
  for (double v : ha.data) ma = std::max(ma, std::abs(v));
  for (double v : hb.data) mb = std::max(mb, std::abs(v));
  CHECK(mb == doctest::Approx(2 * ma).epsilon(0.05));

  for (const char* bad : {"--wave-amplitude 0", "--wavelength -1", "--width 4", "--wave-amplitude 40"}) {
    auto r = test::runCli(std::string("synth nerfrac-primary-sine --size tiny ") + bad + " -o " + (dir / "c"));
    INFO(bad << ": " << r.output);
    CHECK(r.exitCode != 0);
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    CHECK(!fs::exists(dir / "c"));
  }
}

TEST_CASE("synth: poses_bounds.npy holds the same cameras as the Blender transforms") {
  TempDir dir;
  auto r = test::runCli("synth nerfrac-primary-sine --size tiny -o " + (dir / "d"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  NpyArray poses = readNpy(dir / "d/poses_bounds.npy");
  REQUIRE(poses.shape == std::vector<size_t>{9, 17});
  auto train = readJson(dir / "d/transforms_train.json"), test = readJson(dir / "d/transforms_test.json");
  REQUIRE(train["frames"].size() == 8);
  REQUIRE(test["frames"].size() == 1);
  // images/000 is the held-out test view, images/001.. the training views in order.
  for (size_t row = 0; row < 9; row++) {
    const auto& frame = row == 0 ? test["frames"][0] : train["frames"][row - 1];
    const double* p = &poses.data[row * 17];
    auto at = [&](int r, int c) { return p[r * 5 + c]; };
    // LLFF columns [down, right, back] -> camera-to-world [right, up, back] as LLFF loaders do.
    for (int r = 0; r < 3; r++) {
      const auto& m = frame["transform_matrix"][r];
      CHECK(at(r, 1) == doctest::Approx(m[0].get<double>()).epsilon(1e-12));   // right
      CHECK(-at(r, 0) == doctest::Approx(m[1].get<double>()).epsilon(1e-12));  // up
      CHECK(at(r, 2) == doctest::Approx(m[2].get<double>()).epsilon(1e-12));   // back
      CHECK(at(r, 3) == doctest::Approx(m[3].get<double>()).epsilon(1e-12));   // centre
    }
    CHECK(at(0, 4) == frame["h"].get<double>());
    CHECK(at(1, 4) == frame["w"].get<double>());
    CHECK(at(2, 4) == doctest::Approx(frame["fl_x"].get<double>()));
    // near and far bracket the scene: positive, ordered, around the 1.5 m camera-to-floor distance.
    CHECK(p[15] > 0.5);
    CHECK(p[16] > p[15]);
    CHECK(p[16] < 2.5);
    CHECK(readFile(dir / ("d/images/00" + std::to_string(row) + ".png")) ==
          readFile(dir / ("d/" + frame["file_path"].get<std::string>().substr(2) + ".png")));
  }
}

TEST_CASE("synth: bad arguments give one clear error and a non-zero exit and leave no output") {
  TempDir dir;
  auto unknown = test::runCli("synth no-such-preset --size tiny -o " + (dir / "x"));
  CHECK(unknown.exitCode != 0);
  CHECK(unknown.output.find("unknown preset 'no-such-preset'") != std::string::npos);
  CHECK(std::count(unknown.output.begin(), unknown.output.end(), '\n') == 1);

  auto size = test::runCli("synth desk --size huge -o " + (dir / "x"));
  CHECK(size.exitCode != 0);
  CHECK(size.output.find("--size must be tiny or full") != std::string::npos);

  auto noOut = test::runCli("synth desk --size tiny");
  CHECK(noOut.exitCode != 0);
  CHECK(noOut.output.find("-o DIR is required") != std::string::npos);

  // Under a regular file: the folder cannot be created.
  writeTextAtomic(dir / "file", "x");
  auto unwritable = test::runCli("synth desk --size tiny -o " + (dir / "file/out"));
  CHECK(unwritable.exitCode != 0);
  CHECK(unwritable.output.find("cannot create output folder") != std::string::npos);
  CHECK(std::count(unwritable.output.begin(), unwritable.output.end(), '\n') == 1);

  auto proc = test::runCli("synth desk --size tiny -o /proc/refrax-synth-out");
  CHECK(proc.exitCode != 0);
  CHECK(proc.output.find("cannot create output folder /proc/refrax-synth-out") != std::string::npos);
  CHECK(std::count(proc.output.begin(), proc.output.end(), '\n') == 1);

  // A non-empty folder is not overwritten.
  fs::create_directories(dir.path / "full");
  writeTextAtomic(dir / "full/keep.txt", "x");
  auto full = test::runCli("synth desk --size tiny -o " + (dir / "full"));
  CHECK(full.exitCode != 0);
  CHECK(full.output.find("not empty") != std::string::npos);
  CHECK(filesUnder(dir.path) == std::vector<std::string>{"file", "full/keep.txt"});
  CHECK(!fs::exists(dir.path / "x"));
}


TEST_CASE("synth: water.json and the height map and the glTF mesh describe the same surface") {
  TempDir dir;
  auto r = test::runCli("synth nerfrac-hybrid --size tiny --seed 3 -o " + (dir / "h"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  auto water = readJson(dir / "h/water.json");
  CHECK(water["ior"].get<double>() == 1.1);
  const auto& surface = water["surface"];
  REQUIRE(surface["type"] == "wave_sum");
  REQUIRE(surface["directional_waves"].size() == 1);
  REQUIRE(surface["radial_ripples"].size() == 1);
  std::vector<double> domain = water["height_map"]["domain"].get<std::vector<double>>();
  CHECK(domain == water["domain"].get<std::vector<double>>());

  NpyArray hm = readNpy(dir / "h/water_gt_height.npy");
  REQUIRE(hm.shape.size() == 2);
  size_t ny = hm.shape[0], nx = hm.shape[1];
  double range = 0;
  for (size_t j = 0; j < ny; j++)
    for (size_t i = 0; i < nx; i++) {
      double x = domain[0] + (domain[2] - domain[0]) * double(i) / double(nx - 1), y = domain[1] + (domain[3] - domain[1]) * double(j) / double(ny - 1);
      double h = test::heightFromJson(surface, x, y);
      CHECK(hm.data[j * nx + i] == doctest::Approx(h).epsilon(1e-6));
      range = std::max(range, std::abs(h));
    }
  CHECK(range > 0.01);  // the surface is not flat

  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  REQUIRE(loader.LoadASCIIFromFile(&model, &err, &warn, dir / "h/water_gt.gltf"));
  REQUIRE(model.meshes.size() == 1);
  const auto& prim = model.meshes[0].primitives[0];
  const auto& acc = model.accessors[prim.attributes.at("POSITION")];
  const auto& view = model.bufferViews[acc.bufferView];
  const float* pos = reinterpret_cast<const float*>(model.buffers[view.buffer].data.data() + view.byteOffset + acc.byteOffset);
  REQUIRE(acc.count > 100);
  for (size_t v = 0; v < acc.count; v++) {
    const float* p = pos + 3 * v;
    CHECK(p[0] >= domain[0] - 1e-6);
    CHECK(p[0] <= domain[2] + 1e-6);
    CHECK(p[2] == doctest::Approx(test::heightFromJson(surface, p[0], p[1])).epsilon(1e-6));
  }
  const auto& idx = model.accessors[prim.indices];
  CHECK(idx.count == 6 * (size_t(std::sqrt(double(acc.count))) - 1) * (size_t(std::sqrt(double(acc.count))) - 1));
}

TEST_CASE("synth: masks mark the pixels whose rays meet the water domain") {
  SynthScene scene = markerScene(0.4, {0, 0});
  WaveSurface small;  // flat water over a 0.4 m square, seen from 0.6 m with a 60 degree view
  small.domain[0] = small.domain[1] = -0.2;
  small.domain[2] = small.domain[3] = 0.2;
  SynthCamera cam = downwardCamera({0.05, 0.02, 0.6}, 64, 48, 60 * M_PI / 180);
  RenderedView v = renderView(scene, &small, 1.33, cam, RenderSettings{}, 3);
  int inside = 0, outside = 0;
  for (int y = 0; y < v.height; y++)
    for (int x = 0; x < v.width; x++) {
      glm::dvec3 d = cameraRayDirection(cam, x + 0.5, y + 0.5), o = cameraCentre(cam);
      glm::dvec2 p = glm::dvec2(o) + glm::dvec2(d) * (-o.z / d.z);  // where the pixel centre meets z = 0
      double margin = 0.01;  // about one pixel at this distance
      float m = v.mask[size_t(y) * v.width + x];
      if (std::abs(p.x) < 0.2 - margin && std::abs(p.y) < 0.2 - margin) {
        CHECK(m == 1.0f);
        inside++;
      } else if (std::abs(p.x) > 0.2 + margin || std::abs(p.y) > 0.2 + margin) {
        CHECK(m == 0.0f);
        outside++;
      }
    }
  CHECK(inside > 300);
  CHECK(outside > 300);
}

TEST_CASE("synth: a cancelled generation leaves neither the output folder nor a temporary one") {
  TempDir dir;
  const char* source = std::getenv("REFRAX_SOURCE_DIR");  // a copied build's assets (scripts/gpu-check.sh --bundle)
  SynthPreset preset = makeSynthPreset("toys-topdown", SynthSize::Tiny, 1, std::string(source ? source : REFRAX_SOURCE_DIR) + "/assets/textures");
  std::atomic<bool> cancel{true};
  SynthWriteOptions o;
  o.cancel = &cancel;
  CHECK_THROWS_AS(generateSynthDataset(preset, dir / "out", o), Error);
  CHECK(filesUnder(dir.path).empty());
  CHECK(fs::is_empty(dir.path));
  cancel = false;
  generateSynthDataset(preset, dir / "out", o);
  CHECK(fs::exists(dir.path / "out" / "water.json"));
  int entries = 0;
  for (auto& e : fs::directory_iterator(dir.path)) entries += e.is_directory() ? 1 : 100;
  CHECK(entries == 1);
}

TEST_CASE("synth: the triangle BVH returns the closest hit that brute force finds") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(0, 1);
  SceneBuilder b;
  for (int i = 0; i < 12; i++) {
    glm::dvec3 c(U(rng) * 2 - 1, U(rng) * 2 - 1, -U(rng));
    if (i % 3 == 0) b.sphere(c, 0.05 + 0.2 * U(rng), 0, 16);
    else if (i % 3 == 1) b.box(c, {0.05 + 0.2 * U(rng), 0.05 + 0.2 * U(rng), 0.05 + 0.2 * U(rng)}, U(rng) * 3, 0);
    else b.cylinder(c, 0.05 + 0.1 * U(rng), 0.1 + 0.3 * U(rng), 0, 12);
  }
  b.floorRect(-2, -2, 2, 2, -1.2, 0);
  std::vector<MeshTriangle> all = b.triangles;
  TriangleBvh bvh = buildTriangleBvh(b.triangles);
  // 1,800 rays aimed at points of the floor (each must hit something: the count below keeps
  // the test from passing on misses alone), 200 in random downward directions (some miss).
  int hits = 0;
  for (int r = 0; r < 2000; r++) {
    glm::dvec3 o(U(rng) * 3 - 1.5, U(rng) * 3 - 1.5, 0.5 + U(rng));
    glm::dvec3 d = r < 1800 ? glm::normalize(glm::dvec3(U(rng) * 3.6 - 1.8, U(rng) * 3.6 - 1.8, -1.2) - o)
                            : glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, -U(rng)));
    std::optional<TriangleHit> brute;
    for (size_t i = 0; i < all.size(); i++) {
      auto h = intersectTriangle(all[i], o, d, 1e-9, brute ? brute->t : 1e30);
      if (h) {
        brute = h;
        brute->triangle = int(i);
      }
    }
    auto fast = closestTriangleHit(bvh, o, d, 1e-9, 1e30);
    REQUIRE(bool(fast) == bool(brute));
    if (!fast) continue;
    hits++;
    CHECK(fast->t == doctest::Approx(brute->t).epsilon(1e-12));
    glm::dvec3 pf = o + fast->t * d;
    CHECK(glm::length(pf - (o + brute->t * d)) < 1e-9);
  }
  CHECK(hits >= 1790);
}

TEST_CASE("synth: --dry renders the same views without the water, as the water-removal views show the scene") {
  const std::string wet = test::tinyDataset("nerfrac-primary-sine"), dry = test::tinyDataset("nerfrac-primary-sine", "--dry");
  // The dry test view is the wet dataset's water-removal view of the same camera (up to the
  // antialiasing jitter), and far from the view through the water.
  const Image dryTest = readPng(dry + "/test/000.png"), wetTest = readPng(wet + "/test/000.png");
  const Image wetAir = readPng(wet + "/test_air/000.png");
  const double toAir = psnr(dryTest, wetAir), toWet = psnr(dryTest, wetTest);
  INFO("dry test view vs the wet one's water removed: " << toAir << " dB, vs through the water: " << toWet << " dB");
  CHECK(toAir > 24);  // 4 jittered samples per pixel of fine textures: 27 dB measured
  CHECK(toWet < toAir - 6);  // 10 dB measured
  CHECK(readPng(dry + "/train/000.png").pixels != readPng(wet + "/train/000.png").pixels);
  // the same cameras and water.json, marked dry; no masks named
  const nlohmann::json dryWater = readJson(dry + "/water.json"), wetWater = readJson(wet + "/water.json");
  CHECK(dryWater.at("dry") == true);
  CHECK(!dryWater.contains("masks"));
  CHECK(dryWater.at("ior") == wetWater.at("ior"));
  CHECK(dryWater.at("domain") == wetWater.at("domain"));
  CHECK(readJson(dry + "/transforms_train.json").at("frames")[0].at("transform_matrix") ==
        readJson(wet + "/transforms_train.json").at("frames")[0].at("transform_matrix"));
  CHECK(!readJson(dry + "/transforms_train.json").at("frames")[0].contains("mask_path"));
}

namespace {

// Bilinear sample of channel c at continuous image point (u, v) (pixel centres at i + 0.5).
double sampleBilinear(const Image& im, double u, double v, int c) {
  const double x = u - 0.5, y = v - 0.5;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int i, int j) { return double(im.at(std::clamp(i, 0, im.width - 1), std::clamp(j, 0, im.height - 1), c)); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

// Mean absolute difference between a lens view and the pinhole view of the same camera
// resampled where the lens's rays land in it (throughLens), or read at the same pixel (not).
double lensViewDifference(const View& lens, const View& pinhole, bool throughLens, size_t& compared) {
  double sum = 0;
  compared = 0;
  for (int y = 0; y < lens.image.height; y++)
    for (int x = 0; x < lens.image.width; x++) {
      glm::dvec2 uv(x + 0.5, y + 0.5);
      if (throughLens && !pinhole.camera.project(lens.camera.position() + lens.camera.rayDirection(x + 0.5, y + 0.5), uv)) continue;
      if (uv.x < 1 || uv.y < 1 || uv.x > pinhole.image.width - 1 || uv.y > pinhole.image.height - 1) continue;
      for (int c = 0; c < 3; c++) sum += std::abs(lens.image.at(x, y, c) - sampleBilinear(pinhole.image, uv.x, uv.y, c));
      compared++;
    }
  return sum / double(3 * std::max<size_t>(compared, 1));
}

}  // namespace

TEST_CASE("synth: --camera-model renders every view through its lens, written as transforms.json's lens fields" * doctest::test_suite("one-backend")) {
  // The pinhole view of the same camera, resampled where each lens ray lands in it, is the
  // lens view (up to the texture's aliasing); read at the same pixels it is not. A synthesiser
  // that wrote the lens but rendered a pinhole, or bent the rays the other way, fails.
  TempDir dir;
  for (const char* model : {"pinhole", "opencv", "fisheye"}) {
    auto r = test::runCli(std::string("synth nerfrac-primary-sine --size tiny --width 128 --dry --camera-model ") + model + " -o " + (dir / model));
    REQUIRE_MESSAGE(r.exitCode == 0, r.output);
  }
  const Dataset pinhole = loadDataset(dir / "pinhole");
  CHECK(fs::exists(dir / "pinhole/poses_bounds.npy"));
  for (const char* model : {"opencv", "fisheye"}) {
    INFO(model);
    const std::string folder = dir / model;
    CHECK_FALSE(fs::exists(folder + "/poses_bounds.npy"));  // LLFF has no lens
    const std::string camera = readJson(folder + "/transforms_train.json")["frames"][0]["camera_model"].get<std::string>();
    CHECK(camera == (std::string(model) == "opencv" ? "OPENCV" : "OPENCV_FISHEYE"));
    const Dataset d = loadDataset(folder);
    for (size_t i : {size_t(0), size_t(4)}) {
      const View &lens = d.split("train")[i], &pin = pinhole.split("train")[i];
      CHECK(lens.camera.lens.kind == (std::string(model) == "opencv" ? LensKind::RadialTangential : LensKind::Fisheye));
      size_t through = 0, same = 0;
      const double resampled = lensViewDifference(lens, pin, true, through), unmapped = lensViewDifference(lens, pin, false, same);
      MESSAGE(std::string(model) << " view " << i << ": " << resampled << " through the lens (" << through << " pixels), " << unmapped << " unmapped");
      CHECK(through > size_t(lens.image.width * lens.image.height) / (std::string(model) == "opencv" ? 2 : 16));  // the fisheye sees far past the pinhole
      CHECK(resampled < 0.35 * unmapped);
      CHECK(resampled < 0.045);  // measured 0.017 (opencv), 0.034 (fisheye); rendered as pinholes 0.056-0.064
    }
  }
  auto random = test::runCli("synth random --seed 3 --size tiny --camera-model fisheye -o " + (dir / "r"));
  CHECK(random.exitCode != 0);
  CHECK(random.output.find("--camera-model is for the presets") != std::string::npos);
  auto bad = test::runCli("synth desk --size tiny --camera-model equirect -o " + (dir / "b"));
  CHECK(bad.exitCode != 0);
  CHECK(bad.output.find("--camera-model must be pinhole, opencv or fisheye") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "b"));
}

// The bed's truth on a floor whose only mark is a small white square: a flat floor's elevation
// everywhere, the square where the grid's own layout puts it (water.json's "bottom"), in the
// written files. The square (4 texels of 7.8 mm, 8 cells of the grid) is centred half way
// between grid vertices, so 8 x 8 vertices see it, half a cell clear of its edges: a grid
// shifted by half a cell, or a flipped orthophoto, moves its centroid by half a cell or more.
TEST_CASE("synth: the bottom truth holds the floor's elevation and its colour seen straight down, on the height map's grid, north up") {
  const double depth = 0.4, cell = 1.0 / 256;  // 257 vertices over the domain [-0.5, 0.5]^2, inside the 2 m floor
  const glm::dvec2 marker(-0.5 + 160.5 * cell, -0.5 + 100.5 * cell);
  SynthPreset p;
  p.name = "marker";
  p.scene = markerScene(depth, marker);
  p.water.domain[0] = p.water.domain[1] = -0.5;
  p.water.domain[2] = p.water.domain[3] = 0.5;
  p.heightMapSize = 257;
  p.meshGridSize = 9;
  p.train = gridCameras(0, 0, 0.8, 0.2, 16, 16, 45 * M_PI / 180);
  p.test = {p.train[4]};
  p.air = p.test;
  TempDir dir;
  SynthWriteOptions o;
  generateSynthDataset(p, dir / "d", o);
  NpyArray elevation = readNpy(dir / "d/bottom_gt_height.npy");
  Image ortho = readPng(dir / "d/bottom_gt_ortho.png");
  REQUIRE(elevation.shape == std::vector<size_t>{257, 257});
  REQUIRE(ortho.width == 257);
  REQUIRE(ortho.height == 257);
  for (double z : elevation.data) REQUIRE(z == doctest::Approx(-depth).epsilon(1e-6));
  // The white vertices' centroid, each placed by the documented layout.
  glm::dvec2 sum(0);
  int white = 0;
  for (int r = 0; r < 257; r++)
    for (int i = 0; i < 257; i++) {
      const int j = 256 - r;  // PNG row r is grid row ny - 1 - r
      if (ortho.pixels[(size_t(r) * 257 + i) * ortho.channels] < 0.5f) continue;
      sum += glm::dvec2(-0.5 + i * cell, -0.5 + j * cell);
      white++;
    }
  INFO("white vertices " << white);
  REQUIRE(white == 64);
  CHECK(glm::length(sum / double(white) - marker) < 0.25 * cell);
  nlohmann::json bottom = readJson(dir / "d/water.json")["bottom"];
  CHECK(bottom["elevation"] == "bottom_gt_height.npy");
  CHECK(bottom["orthophoto"] == "bottom_gt_ortho.png");
  CHECK(bottom["shape"] == nlohmann::json({257, 257}));
}

