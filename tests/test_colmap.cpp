// COLMAP datasets (engine/dataset/colmap_model.h, engine/dataset/colmap.cpp): a synthetic
// dataset's cameras written as a COLMAP model in a frame of COLMAP's own (rotated, scaled,
// moved), with sparse points on the pool floor and the dry rim, must load as the same rig:
// up recovered, the same angles and proportions, the water height found at the rim.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/dataset/dataset.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/train/init_gaussians.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

// COLMAP's frame from the dataset's: x_colmap = scale * rotation * x + shift.
struct Similarity {
  glm::dmat3 rotation;
  double scale;
  glm::dvec3 shift;
  glm::dvec3 apply(const glm::dvec3& p) const { return scale * (rotation * p) + shift; }
};

Similarity someFrame() {
  glm::dmat4 r = glm::rotate(glm::dmat4(1.0), 1.1, glm::normalize(glm::dvec3(0.3, -0.8, 0.5)));
  return {glm::dmat3(r), 2.5, glm::dvec3(4.0, -1.5, 7.0)};
}

// The dataset's views as a COLMAP model in `frame`, images copied beside it; sparse points
// on the floor (depth under the water) and on a rim at the water height (a fifth of them).
ColmapModel writeAsColmap(const Dataset& d, const Similarity& frame, double waterHeight, const fs::path& out, bool binary) {
  ColmapModel m;
  fs::create_directories(out / "images");
  fs::create_directories(out / "sparse/0");
  uint32_t id = 1;
  for (const char* split : {"train", "test"})
    for (const View& v : d.split(split)) {
      const Camera& c = v.camera;
      ColmapCamera cam;
      cam.id = id;
      cam.model = id % 2 ? "PINHOLE" : "SIMPLE_PINHOLE";
      cam.width = uint64_t(c.width);
      cam.height = uint64_t(c.height);
      cam.params = id % 2 ? std::vector<double>{c.fx, c.fy, c.cx, c.cy} : std::vector<double>{c.fx, c.cx, c.cy};
      if (id % 2 == 0) REQUIRE(c.fx == c.fy);
      m.cameras[id] = cam;
      // camera-to-world in COLMAP's frame, OpenCV axes (x right, y down, z forward)
      glm::dmat3 axes(frame.rotation * c.right(), -(frame.rotation * c.up()), -(frame.rotation * c.back()));
      glm::dmat3 worldToCamera = glm::transpose(axes);
      ColmapImage im;
      im.id = id;
      im.cameraId = id;
      im.q = colmapQuaternion(worldToCamera);
      im.t = -(worldToCamera * frame.apply(c.position()));
      im.name = "view_" + std::to_string(id) + ".png";
      writePng((out / "images" / im.name).string(), v.image);
      m.images.push_back(im);
      id++;
    }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (int i = 0; i < 200; i++) {
    ColmapPoint p;
    const bool rim = i % 5 == 0;
    p.position = frame.apply(glm::dvec3(u(rng), u(rng), rim ? waterHeight : waterHeight - 0.5 + 0.1 * u(rng)));
    p.colour = glm::dvec3(0.5);
    m.points.push_back(p);
  }
  writeColmapModel((out / "sparse/0").string(), m, binary);
  return m;
}

double angleToZ(const glm::dvec3& v) { return std::acos(glm::clamp(glm::normalize(v).z, -1.0, 1.0)); }

}  // namespace

TEST_CASE("COLMAP model: text and binary files round-trip cameras, poses and points") {
  test::TrainTempDir dir;
  ColmapModel m;
  m.cameras[3] = ColmapCamera{3, "PINHOLE", 640, 480, {500.5, 501.25, 320.1, 239.9}};
  m.cameras[7] = ColmapCamera{7, "SIMPLE_PINHOLE", 64, 48, {60.0, 32.0, 24.0}};
  m.images.push_back(ColmapImage{1, glm::normalize(glm::dvec4(0.9, 0.1, -0.3, 0.2)), glm::dvec3(0.5, -1.25, 3.0), 3, "a/b c.jpg"});
  m.images.push_back(ColmapImage{9, glm::dvec4(1, 0, 0, 0), glm::dvec3(0), 7, "z.png"});
  m.points.push_back(ColmapPoint{glm::dvec3(1, 2, 3), glm::dvec3(1, 0, 0), 0.5, 0});
  for (bool binary : {false, true}) {
    const std::string folder = dir / (binary ? "bin" : "txt");
    fs::create_directories(folder);
    writeColmapModel(folder, m, binary);
    CHECK(fileExists(folder + (binary ? "/images.bin" : "/images.txt")));
    ColmapModel back = readColmapModel(folder);
    REQUIRE(back.cameras.size() == 2);
    CHECK(back.cameras[3].params == m.cameras[3].params);
    CHECK(back.cameras[7].model == "SIMPLE_PINHOLE");
    REQUIRE(back.images.size() == 2);
    CHECK(back.images[0].name == "a/b c.jpg");  // names may hold spaces
    for (int k = 0; k < 4; k++) CHECK(back.images[0].q[k] == doctest::Approx(m.images[0].q[k]).epsilon(1e-15));
    CHECK(back.images[0].t.y == -1.25);
    CHECK(back.images[1].cameraId == 7);
    REQUIRE(back.points.size() == 1);
    CHECK(back.points[0].position.z == 3);
  }
  // the quaternion conventions: colmapRotation inverts colmapQuaternion
  glm::dmat3 r = colmapRotation(m.images[0].q);
  glm::dvec4 q = colmapQuaternion(r);
  for (int k = 0; k < 4; k++) CHECK(q[k] == doctest::Approx(m.images[0].q[k]).epsilon(1e-12));
  // malformed: a camera that names too few parameters, an image of an unknown camera, a cut file
  writeTextAtomic(dir / "txt/cameras.txt", "1 PINHOLE 64 48 50 50 32\n");
  CHECK_THROWS_WITH_AS(readColmapModel(dir / "txt"), doctest::Contains("has 3 parameters, the model has 4"), Error);
  std::string images = readFile(dir / "bin/images.bin");
  writeFileAtomic(dir / "bin/images.bin", images.data(), images.size() - 5);
  CHECK_THROWS_WITH_AS(readColmapModel(dir / "bin"), doctest::Contains("images.bin: truncated"), Error);
}

TEST_CASE("COLMAP dataset: a rig in COLMAP's own frame loads with up, proportions and the water height recovered" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset original = loadDataset(data);
  REQUIRE(original.water.height);
  const double water = *original.water.height;
  const Similarity frame = someFrame();
  for (bool binary : {true, false}) {
    const fs::path folder = fs::path(dir.path) / (binary ? "colmap-bin" : "colmap-txt");
    writeAsColmap(original, frame, water, folder, binary);
    Dataset d = loadDataset(folder.string());
    CHECK(d.format == "colmap");
    std::vector<const View*> a, b;  // original and loaded, in the model's order (train then test, by id)
    for (const char* split : {"train", "test"})
      for (const View& v : original.split(split)) a.push_back(&v);
    std::vector<const View*> loaded;
    for (const auto& [name, views] : d.splits)
      for (const View& v : views) loaded.push_back(&v);
    REQUIRE(loaded.size() == a.size());
    b.resize(a.size());
    for (const View* v : loaded) {  // images/view_<id>.png, ids from 1 in a's order
      size_t id = std::stoul(v->name.substr(v->name.find('_') + 1));
      REQUIRE(id >= 1);
      REQUIRE(id <= a.size());
      b[id - 1] = v;
    }
    // Up recovered: every camera's tilt from the vertical is the original's.
    for (size_t i = 0; i < a.size(); i++) {
      INFO("view " << i);
      CHECK(angleToZ(b[i]->camera.back()) == doctest::Approx(angleToZ(a[i]->camera.back())).epsilon(1e-6));
      CHECK(b[i]->camera.fx == a[i]->camera.fx);
      CHECK(b[i]->camera.cy == a[i]->camera.cy);
      CHECK(b[i]->image.pixels == a[i]->image.pixels);
    }
    // Proportions: distances between cameras all scale by one factor; heights above the water too.
    const double s = glm::length(b[1]->camera.position() - b[0]->camera.position()) /
                     glm::length(a[1]->camera.position() - a[0]->camera.position());
    for (size_t i = 2; i < a.size(); i++)
      CHECK(glm::length(b[i]->camera.position() - b[0]->camera.position()) ==
            doctest::Approx(s * glm::length(a[i]->camera.position() - a[0]->camera.position())).epsilon(1e-9));
    // The water height found at the rim points: each camera as high above it as before (scaled).
    REQUIRE(d.water.height);
    for (size_t i = 0; i < a.size(); i++)
      CHECK(b[i]->camera.position().z - *d.water.height == doctest::Approx(s * (a[i]->camera.position().z - water)).epsilon(1e-6));
    bool explained = false;
    for (const std::string& note : d.notes) explained = explained || note.find("estimated: the 95th percentile") != std::string::npos;
    CHECK(explained);
    if (!binary) continue;
    // The CLI: inspect prints the derived frame; a short training run takes the folder.
    test::CliResult inspect = test::runCli("inspect " + folder.string());
    CHECK(inspect.exitCode == 0);
    CHECK(inspect.output.find("(colmap)") != std::string::npos);
    CHECK(inspect.output.find("frame: up (") != std::string::npos);
    // --init-points: the Gaussians start at the floor's points (40 of the 200 are the rim's, above the water)
    test::CliResult train = test::runCli("train " + folder.string() + " -o " + (dir / "run") +
                                         " --steps 4 --gaussians 200 --patch 16 --checkpoint-every 0 --init-points");
    INFO(train.output);
    CHECK(train.exitCode == 0);
    CHECK(train.output.find("200 Gaussians (160 at sparse points)") != std::string::npos);
    CHECK(fileExists(dir / "run/metrics.json"));
    CHECK(readFile(dir / "run/config.json").find("\"init_points\": true") != std::string::npos);
  }
}

TEST_CASE("COLMAP dataset: every lens model loads, FOV and THIN_PRISM_FISHEYE are refused with the fix, missing and extra images are counted" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset original = loadDataset(data);
  const fs::path folder = fs::path(dir.path) / "colmap";
  ColmapModel m = writeAsColmap(original, someFrame(), *original.water.height, folder, false);

  fs::remove(folder / "images" / m.images[0].name);                      // registered, not on disk
  fs::copy_file(folder / "images" / m.images[1].name, folder / "images/extra.png");  // on disk, not registered
  Dataset d = loadDataset(folder.string());
  size_t views = 0;
  for (const auto& [name, v] : d.splits) views += v.size();
  CHECK(views == m.images.size() - 1);
  std::string notes;
  for (const std::string& n : d.notes) notes += n + "\n";
  CHECK(notes.find("1 of the model's " + std::to_string(m.images.size()) + " images are not in") != std::string::npos);
  CHECK(notes.find("1 files in") != std::string::npos);

  // every distortion model loads, traced through its lens; the two without a ray in Refrax are
  // refused with the fix; in the text and the binary format
  ColmapCamera& distorted = m.cameras[m.images[1].cameraId];  // a camera of an image on disk
  const ColmapCamera pinhole = distorted;
  const std::vector<std::tuple<std::string, std::vector<double>, LensKind>> models = {
      {"SIMPLE_RADIAL", {50, 32, 24, 0.1}, LensKind::RadialTangential},
      {"RADIAL", {50, 32, 24, 0.1, 0.01}, LensKind::RadialTangential},
      {"OPENCV", {50, 50, 32, 24, 0.1, 0.01, 0, 0}, LensKind::RadialTangential},
      {"FULL_OPENCV", {50, 50, 32, 24, 0.1, 0.01, 0, 0, 0.001, 0, 0, 0}, LensKind::RadialTangential},
      {"OPENCV_FISHEYE", {50, 50, 32, 24, 0.01, 0, 0, 0}, LensKind::Fisheye},
      {"SIMPLE_RADIAL_FISHEYE", {50, 32, 24, 0.01}, LensKind::Fisheye},
      {"RADIAL_FISHEYE", {50, 32, 24, 0.01, 0.001}, LensKind::Fisheye}};
  auto writeModel = [&](bool binary) {
    fs::remove_all(folder / "sparse/0");
    fs::create_directories(folder / "sparse/0");
    writeColmapModel((folder / "sparse/0").string(), m, binary);
  };
  for (const auto& [model, params, kind] : models)
    for (bool binary : {false, true}) {
      INFO(model << (binary ? " (binary)" : " (text)"));
      distorted.model = model;
      distorted.params = params;
      writeModel(binary);
      Dataset loaded = loadDataset(folder.string());
      bool found = false;
      for (const auto& [name, views] : loaded.splits)
        for (const View& v : views)
          if (v.name.find(m.images[1].name) != std::string::npos) {
            found = true;
            CHECK(v.camera.lens.kind == kind);
            CHECK(v.camera.lens.radial[0] == params[params.size() == 4 || params.size() == 5 ? 3 : 4]);
            CHECK(v.camera.fx == params[0]);
          }
      CHECK(found);
    }
  for (const std::string model : {"FOV", "THIN_PRISM_FISHEYE"}) {
    distorted.model = model;
    distorted.params = std::vector<double>(colmapParamCount(model), 0.0);
    distorted.params[0] = distorted.params[1] = 50;
    writeModel(false);
    CHECK_THROWS_WITH_AS(loadDataset(folder.string()), doctest::Contains("colmap image_undistorter"), Error);
    CHECK_THROWS_WITH_AS(loadDataset(folder.string()), doctest::Contains(model.c_str()), Error);
  }
  distorted = pinhole;

  DatasetOptions up;
  up.up = glm::dvec3(0, 0, 1);
  CHECK_THROWS_WITH_AS(loadDataset(data, up), doctest::Contains("--up applies to COLMAP and nerfstudio datasets only"), Error);
}

TEST_CASE("COLMAP dataset: a low ring of cameras takes up from the plane of their centres" * doctest::test_suite("one-backend")) {
  // Eight cameras 15 degrees above the horizon looking at a point off the centre: their
  // viewing directions agree to only about sin(15) = 0.26, so up is the normal of the plane
  // through their centres (their mean viewing direction is tilted by the off-centre target).
  test::TrainTempDir dir;
  Dataset ring;
  ring.splits["train"];
  for (int i = 0; i < 8; i++) {
    const double a = 2 * M_PI * i / 8, e = 15 * M_PI / 180;
    const glm::dvec3 eye(2 * std::cos(e) * std::cos(a), 2 * std::cos(e) * std::sin(a), 2 * std::sin(e));
    const glm::dvec3 back = glm::normalize(eye - glm::dvec3(0.7, 0.3, 0)), right = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), back));
    View v;
    v.camera.cameraToWorld = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(glm::cross(back, right), 0), glm::dvec4(back, 0), glm::dvec4(eye, 1));
    v.camera.width = v.camera.height = 8;
    v.camera.fx = v.camera.fy = 8;
    v.camera.cx = v.camera.cy = 4;
    v.image = Image{8, 8, 3, std::vector<float>(8 * 8 * 3, 0.5f)};
    ring.splits["train"].push_back(v);
  }
  ring.splits["test"];
  const Similarity frame = someFrame();
  const fs::path folder = fs::path(dir.path) / "ring";
  writeAsColmap(ring, frame, -0.2, folder, true);
  Dataset d = loadDataset(folder.string());
  // The loaded frame's +Z is the original up: every camera keeps its angle to the vertical.
  const glm::dvec3 up = glm::transpose(glm::dmat3(d.normalization)) * glm::dvec3(0, 0, 1);
  CHECK(glm::dot(glm::normalize(up), frame.rotation * glm::dvec3(0, 0, 1)) == doctest::Approx(1).epsilon(1e-9));
  for (const auto& [split, views] : d.splits)
    for (const View& v : views) {
    const size_t id = std::stoul(v.name.substr(v.name.find('_') + 1));  // images/view_<id>.png, ids from 1
    CHECK(angleToZ(v.camera.back()) == doctest::Approx(angleToZ(ring.split("train")[id - 1].camera.back())).epsilon(1e-9));
    }
  bool plane = false;
  for (const std::string& note : d.notes) plane = plane || note.find("the normal of the plane of the camera centres") != std::string::npos;
  CHECK(plane);
}

TEST_CASE("Test views: named by index or file name in LLFF and COLMAP datasets, refused where they cannot apply" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");  // written as LLFF beside the Blender files
  Dataset all = loadLlffDataset(data);
  REQUIRE(all.format == "llff");
  const size_t n = all.split("train").size() + all.split("test").size();
  REQUIRE(n >= 5);
  DatasetOptions centre;
  centre.testViews = {"4"};  // NeRFrac's protocol: the centre view of nine
  Dataset d = loadLlffDataset(data, centre);
  REQUIRE(d.split("test").size() == 1);
  CHECK(d.split("train").size() == n - 1);
  std::vector<std::string> names;
  for (const char* split : {"train", "test"})
    for (const View& v : all.split(split)) names.push_back(v.name);
  std::sort(names.begin(), names.end());
  CHECK(d.split("test")[0].name == names[4]);
  // by file name (as the image folder lists it), two at once
  DatasetOptions byName;
  byName.testViews = {fs::path(names[1]).filename().string(), "3"};
  Dataset two = loadLlffDataset(data, byName);
  REQUIRE(two.split("test").size() == 2);
  CHECK(two.split("test")[0].name == names[1]);
  CHECK(two.split("test")[1].name == names[3]);
  // no match, every view held out, a Blender dataset, both flags on the command line
  DatasetOptions bad;
  bad.testViews = {std::to_string(n)};
  const std::string noSuchIndex = "--test-views: '" + std::to_string(n) + "' is neither an image";
  CHECK_THROWS_WITH_AS(loadLlffDataset(data, bad), doctest::Contains(noSuchIndex.c_str()), Error);
  bad.testViews = {"nope.png"};
  CHECK_THROWS_WITH_AS(loadLlffDataset(data, bad), doctest::Contains("--test-views: 'nope.png'"), Error);
  bad.testViews.clear();
  for (size_t i = 0; i < n; i++) bad.testViews.push_back(std::to_string(i));
  CHECK_THROWS_WITH_AS(loadLlffDataset(data, bad), doctest::Contains("no training views remain"), Error);
  CHECK_THROWS_WITH_AS(loadDataset(data, centre), doctest::Contains("applies to LLFF, COLMAP and nerfstudio"), Error);
  test::CliResult both = test::runCli("inspect " + data + " --test-views 4 --llff-hold 2");
  CHECK(both.exitCode != 0);
  CHECK(both.output.find("give one") != std::string::npos);

  // COLMAP: the same selection over the registered images in name order
  const fs::path folder = fs::path(dir.path) / "colmap";
  ColmapModel m = writeAsColmap(all, someFrame(), *all.water.height, folder, true);
  std::vector<std::string> colmapNames;
  for (const ColmapImage& im : m.images) colmapNames.push_back(im.name);
  std::sort(colmapNames.begin(), colmapNames.end());
  Dataset c = loadDataset(folder.string(), centre);
  REQUIRE(c.split("test").size() == 1);
  CHECK(c.split("test")[0].name == "images/" + colmapNames[4]);
  // the choice travels with the run: config.json keeps it, and `refrax eval` evaluates the same view
  test::CliResult train = test::runCli("train " + folder.string() + " --test-views " + colmapNames[2] + " -o " + (dir / "run") +
                                       " --steps 2 --gaussians 100 --patch 8 --checkpoint-every 0");
  INFO(train.output);
  REQUIRE(train.exitCode == 0);
  CHECK(readFile(dir / "run/config.json").find("\"test_views\"") != std::string::npos);
}

TEST_CASE("--init-points: Gaussians at the sparse points under the water (moved to their true depth), none above it") {
  // Points at apparent depths under a flat water at z = 0.5 with IOR 1.5, and two above it.
  std::vector<SparsePoint> points;
  for (int i = 0; i < 10; i++) points.push_back({glm::dvec3(0.1 * i, -0.2 * i, 0.5 - 0.05 * (i + 1)), glm::dvec3(0.1 * i, 0.5, 1)});
  points.push_back({glm::dvec3(0, 0, 0.6), glm::dvec3(1, 0, 0)});  // the dry rim
  points.push_back({glm::dvec3(1, 1, 0.5), glm::dvec3(1, 0, 0)});  // at the water: not under it
  const double boxMin[3] = {-1, -1, -1}, boxMax[3] = {1, 1, 0.5};
  std::mt19937 rng(5);
  size_t used = 0;
  GaussianSet g = initialGaussiansAtPoints(rng, 100, points, 0.5, 1.5, boxMin, boxMax, 0.1, used);
  REQUIRE(used == 10);
  REQUIRE(g.count() == 10);
  std::vector<bool> seen(10, false);
  for (size_t k = 0; k < g.count(); k++) {
    const float* p = g.at(k);
    const int i = int(std::lround(p[f32::kGaussMean] / 0.1));
    REQUIRE(i >= 0);
    REQUIRE(i < 10);
    seen[size_t(i)] = true;
    CHECK(p[f32::kGaussMean + 1] == doctest::Approx(-0.2 * i));
    CHECK(p[f32::kGaussMean + 2] == doctest::Approx(0.5 - 1.5 * 0.05 * (i + 1)));  // apparent depth x IOR
    CHECK(0.28209479177387814 * p[f32::kGaussSH] + 0.5 == doctest::Approx(0.1 * i).epsilon(1e-5));  // the point's colour
  }
  CHECK(std::find(seen.begin(), seen.end(), false) == seen.end());
  // at most `count`: a subset
  GaussianSet few = initialGaussiansAtPoints(rng, 4, points, 0.5, 1.5, boxMin, boxMax, 0.1, used);
  CHECK(used == 4);
  CHECK(few.count() == 4);
  // a dataset without sparse points is refused before any run folder
  test::TrainTempDir dir;
  test::CliResult blender = test::runCli("train " + test::tinyDataset("nerfrac-primary-sine") + " -o " + (dir / "run") + " --steps 2 --init-points");
  CHECK(blender.exitCode != 0);
  CHECK(blender.output.find("--init-points: ") != std::string::npos);
  CHECK(blender.output.find("has no sparse points under the water") != std::string::npos);
  CHECK(blender.output.find("it has no sparse points at all (only COLMAP models carry them") != std::string::npos);
  CHECK(!fs::exists(dir / "run"));
}

TEST_CASE("--init-points on a COLMAP model whose every point is above the water says so, not that only COLMAP models have points" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset original = loadDataset(data);
  const fs::path folder = fs::path(dir.path) / "colmap";
  writeAsColmap(original, someFrame(), *original.water.height, folder, false);
  const Dataset loaded = loadDataset(folder.string());
  REQUIRE(!loaded.points.empty());
  double lowest = loaded.points.front().position.z;
  for (const SparsePoint& p : loaded.points) lowest = std::min(lowest, p.position.z);
  // The water given under every sparse point (in the frame `refrax inspect` prints).
  const std::string under = std::to_string(lowest - 0.05);
  test::CliResult r = test::runCli("train " + folder.string() + " -o " + (dir / "run") + " --steps 2 --init-points --water-height " + under);
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("--init-points: " + folder.string() + " has no sparse points under the water: all 200 of its sparse points lie at or above "
                      "the water height") != std::string::npos);
  CHECK(r.output.find("only COLMAP models carry them") == std::string::npos);
  CHECK(!fs::exists(dir / "run"));
}
