// Dataset loaders (Blender, LLFF, water.json) on tiny datasets written here, every bad input
// giving one clear error, and the scene bounds derived from cameras against worked answers.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/gtc/quaternion.hpp>

#include "engine/dataset/dataset.h"
#include "engine/dataset/ground_truth.h"
#include "engine/dataset/scene_bounds.h"
#include "engine/base/error.h"
#include "engine/io/image_io.h"
#include "engine/io/npy.h"
#include "tests/gpu_test.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

// A fresh folder under the system temp dir, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() / ("refrax_dataset_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string str() const { return path.string(); }
};

void writeImage(const fs::path& p, const Image& image) {
  fs::create_directories(p.parent_path());
  writePng(p.string(), image);
}

void writeText(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// Pixel (x, y, c) of the test images: multiples of 1/255 so 8-bit storage keeps them exactly.
float testValue(int x, int y, int c, int salt) { return float((x * 37 + y * 11 + c * 53 + salt * 7) % 256) / 255.0f; }

Image testImage(int w, int h, int channels, int salt) {
  Image im;
  im.width = w;
  im.height = h;
  im.channels = channels;
  im.pixels.resize(size_t(w) * h * channels);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      for (int c = 0; c < channels; c++) im.at(x, y, c) = testValue(x, y, c, salt);
  return im;
}

std::string matrixJson(const glm::dmat4& m) {
  std::string s = "[";
  for (int r = 0; r < 4; r++) {
    s += r ? ",[" : "[";
    for (int c = 0; c < 4; c++) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.17g", c ? "," : "", m[c][r]);
      s += buf;
    }
    s += "]";
  }
  return s + "]";
}

glm::dmat4 randomPose(std::mt19937& rng) {
  std::normal_distribution<double> N(0.0, 1.0);
  glm::dmat4 m(glm::mat3_cast(glm::normalize(glm::dquat(N(rng), N(rng), N(rng), N(rng)))));
  m[3] = glm::dvec4(N(rng), N(rng), 3.0 + N(rng), 1.0);
  return m;
}

double maxDiff(const glm::dmat4& a, const glm::dmat4& b) {
  double d = 0;
  for (int c = 0; c < 4; c++)
    for (int r = 0; r < 4; r++) d = std::max(d, std::abs(a[c][r] - b[c][r]));
  return d;
}

// The error message of f(), or "" when it does not throw refrax::Error.
template <typename F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

struct BlenderFrame {
  std::string filePath;  // as written in the JSON
  glm::dmat4 pose;
};

std::string transformsJson(const std::string& intrinsics, const std::vector<BlenderFrame>& frames) {
  std::string s = "{" + intrinsics + (intrinsics.empty() ? "" : ",") + "\"frames\":[";
  for (size_t i = 0; i < frames.size(); i++)
    s += (i ? "," : "") + std::string("{\"file_path\":\"") + frames[i].filePath + "\",\"transform_matrix\":" + matrixJson(frames[i].pose) + "}";
  return s + "]}";
}

}  // namespace

TEST_CASE("Blender dataset: splits, poses, intrinsics, extension-less paths, RGBA on the background") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  std::vector<BlenderFrame> train, test, val;
  for (int i = 0; i < 3; i++) {
    train.push_back({"./train/r_" + std::to_string(i), randomPose(rng)});  // no extension, as the Blender scenes
    writeImage(dir.str() + "/train/r_" + std::to_string(i) + ".png", testImage(8, 6, 4, i));
  }
  test.push_back({"test/t_0.png", randomPose(rng)});
  writeImage(dir.str() + "/test/t_0.png", testImage(8, 6, 3, 9));
  val.push_back({"val/v_0", randomPose(rng)});
  writeImage(dir.str() + "/val/v_0.png", testImage(8, 6, 1, 4));  // grey
  const double angle = 0.69;
  writeText(dir.path / "transforms_train.json", transformsJson("\"camera_angle_x\": 0.69", train));
  writeText(dir.path / "transforms_test.json", transformsJson("\"camera_angle_x\": 0.69", test));
  writeText(dir.path / "transforms_val.json", transformsJson("\"camera_angle_x\": 0.69", val));
  writeText(dir.path / "water.json", R"({"ior": 1.1, "height": -0.5, "domain": [-1, -2, 1, 2]})");

  DatasetOptions opt;
  opt.background = glm::dvec3(1.0, 0.5, 0.0);
  Dataset d = loadDataset(dir.str(), opt);
  CHECK(d.format == "blender");
  REQUIRE(d.splits.size() == 3);
  REQUIRE(d.split("train").size() == 3);
  CHECK(d.split("test").size() == 1);
  CHECK(d.split("val").size() == 1);
  CHECK_THROWS_AS(d.split("nope"), Error);
  for (int i = 0; i < 3; i++) {
    const View& v = d.split("train")[i];
    CHECK(maxDiff(v.camera.cameraToWorld, train[i].pose) < 1e-12);
    CHECK(v.camera.width == 8);
    CHECK(v.camera.height == 6);
    CHECK(v.camera.fx == doctest::Approx(4.0 / std::tan(angle / 2)));
    CHECK(v.camera.fy == doctest::Approx(v.camera.fx));
    CHECK(v.camera.cx == 4.0);
    CHECK(v.camera.cy == 3.0);
    REQUIRE(v.image.channels == 3);
    size_t bad = 0;
    for (int y = 0; y < 6; y++)
      for (int x = 0; x < 8; x++)
        for (int c = 0; c < 3; c++) {
          double a = testValue(x, y, 3, i);
          double expect = testValue(x, y, c, i) * a + opt.background[c] * (1 - a);
          if (std::abs(v.image.at(x, y, c) - expect) > 1e-6) bad++;
        }
    CHECK(bad == 0);
  }
  const View& grey = d.split("val")[0];
  CHECK(grey.image.channels == 3);
  CHECK(grey.image.at(5, 4, 2) == doctest::Approx(testValue(5, 4, 0, 4)));
  CHECK(d.split("test")[0].image.at(7, 5, 1) == doctest::Approx(testValue(7, 5, 1, 9)));
  CHECK(d.water.ior == 1.1);
  CHECK(*d.water.height == -0.5);
  CHECK(d.water.domain->yMax == 2.0);
  CHECK(!d.water.depth);

  // instant-ngp intrinsics, a frame overriding fl_x; options override water.json
  writeText(dir.path / "transforms_train.json",
            "{\"fl_x\": 10, \"fl_y\": 12, \"cx\": 3.5, \"cy\": 2.25, \"w\": 8, \"h\": 6, \"frames\": [{\"file_path\": \"train/r_0\", "
            "\"fl_x\": 11, \"transform_matrix\": " + matrixJson(train[0].pose) + "}, {\"file_path\": \"train/r_1\", \"transform_matrix\": " +
                matrixJson(train[1].pose) + "}]}");
  opt.ior = 1.33;
  opt.waterDepth = 2.0;
  d = loadDataset(dir.str(), opt);
  const auto& t = d.split("train");
  CHECK(t[0].camera.fx == 11.0);
  CHECK(t[1].camera.fx == 10.0);
  CHECK(t[1].camera.fy == 12.0);
  CHECK(t[1].camera.cx == 3.5);
  CHECK(t[1].camera.cy == 2.25);
  CHECK(d.water.ior == 1.33);
  CHECK(*d.water.depth == 2.0);
  CHECK(*d.water.height == -0.5);
}

TEST_CASE("bad Blender datasets give one clear error each") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  glm::dmat4 pose = randomPose(rng);
  writeImage(dir.str() + "/a.png", testImage(8, 6, 3, 0));
  writeImage(dir.str() + "/b.png", testImage(7, 6, 3, 0));
  const std::string angle = "\"camera_angle_x\": 0.5";
  auto expectError = [&](const std::string& json, const std::string& fragment) {
    writeText(dir.path / "transforms_train.json", json);
    std::string message = errorOf([&] { loadDataset(dir.str()); });
    INFO("error: '" << message << "', expected to mention '" << fragment << "'");
    CHECK(message.find(fragment) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  };
  CHECK(errorOf([&] { loadDataset(dir.str()); }).find("no dataset") != std::string::npos);
  expectError(transformsJson(angle, {{"missing", pose}}), "does not exist");
  expectError(transformsJson(angle + ", \"w\": 8, \"h\": 6", {{"b.png", pose}}), "expected 8x6");
  expectError(transformsJson(angle, {{"a", pose}, {"b", pose}}), "the split's first is 8x6");
  expectError("{\"camera_angle_x\": 0.5, \"frames\": [", "malformed JSON");
  expectError(transformsJson(angle, {}), "no frames");
  expectError("{\"camera_angle_x\": 0.5}", "missing 'frames'");
  expectError(transformsJson("", {{"a", pose}}), "no intrinsics");
  glm::dmat4 stretched = pose;
  stretched[1] *= 1.5;
  expectError(transformsJson(angle, {{"a", stretched}}), "not orthonormal");
  glm::dmat4 mirrored = pose;
  mirrored[0] = -mirrored[0];
  expectError(transformsJson(angle, {{"a", mirrored}}), "reflection");
  // the first matrix entry replaced by null, then by a number that overflows a double
  auto withFirstEntry = [&](const std::string& token) {
    std::string json = transformsJson(angle, {{"a", pose}});
    size_t start = json.find("\"transform_matrix\":[[") + 21;
    return json.replace(start, json.find(',', start) - start, token);
  };
  expectError(withFirstEntry("null"), "not a number");
  expectError(withFirstEntry("1e999"), "malformed JSON");
  // water.json problems
  writeText(dir.path / "transforms_train.json", transformsJson(angle, {{"a", pose}}));
  writeText(dir.path / "water.json", R"({"ior": 0.5})");
  CHECK(errorOf([&] { loadDataset(dir.str()); }).find("index of refraction") != std::string::npos);
  writeText(dir.path / "water.json", R"({"domain": [0, 0, 1]})");
  CHECK(errorOf([&] { loadDataset(dir.str()); }).find("'domain'") != std::string::npos);
  writeText(dir.path / "water.json", R"({"domain": [0, 0, -1, 1]})");
  CHECK(errorOf([&] { loadDataset(dir.str()); }).find("empty") != std::string::npos);
  writeText(dir.path / "water.json", R"({"height": "low"})");
  CHECK(errorOf([&] { loadDataset(dir.str()); }).find("'height' must be a number") != std::string::npos);
}

namespace {

// poses_bounds.npy rows from camera-to-world matrices in the Blender convention: the LLFF
// rotation columns are [down, right, back] = [-up, right, back].
NpyArray posesBounds(const std::vector<glm::dmat4>& poses, const std::vector<glm::dvec2>& bounds, double H, double W, double focal) {
  NpyArray a;
  a.shape = {poses.size(), 17};
  for (size_t i = 0; i < poses.size(); i++) {
    const glm::dmat4& m = poses[i];
    glm::dvec3 cols[5] = {-glm::dvec3(m[1]), glm::dvec3(m[0]), glm::dvec3(m[2]), glm::dvec3(m[3]), glm::dvec3(H, W, focal)};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 5; c++) a.data.push_back(cols[c][r]);
    a.data.push_back(bounds[i].x);
    a.data.push_back(bounds[i].y);
  }
  return a;
}

}  // namespace

TEST_CASE("LLFF poses_bounds.npy loads back to its cameras up to the documented scale and recentring") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  std::normal_distribution<double> N(0.0, 1.0);
  const int n = 9, factor = 2, W = 16, H = 12;
  const double focal = 30.0;
  std::vector<glm::dmat4> poses;
  std::vector<glm::dvec2> bounds;
  // cameras roughly looking down (-Z) at a scene below, in some arbitrary original frame
  glm::dmat4 frame = randomPose(rng);
  for (int i = 0; i < n; i++) {
    glm::dmat4 tilt(glm::mat3_cast(glm::normalize(glm::dquat(1.0, 0.1 * N(rng), 0.1 * N(rng), 0.1 * N(rng)))));
    tilt[3] = glm::dvec4(N(rng), N(rng), 0.2 * N(rng), 1.0);
    poses.push_back(frame * tilt);
    bounds.push_back(glm::dvec2(2.0 + std::abs(N(rng)), 6.0 + std::abs(N(rng))));
  }
  writeNpy(dir.str() + "/poses_bounds.npy", posesBounds(poses, bounds, H * factor, W * factor, focal), true);
  for (int i = 0; i < n; i++) writeImage(dir.str() + "/images_2/img_" + std::to_string(i) + ".png", testImage(W, H, 3, i));
  DatasetOptions opt;
  opt.llffFactor = factor;
  Dataset d = loadDataset(dir.str(), opt);
  CHECK(d.format == "llff");
  // every 8th view from the first is a test view
  REQUIRE(d.split("test").size() == 2);
  REQUIRE(d.split("train").size() == 7);
  CHECK(d.split("test")[1].name == "images_2/img_8.png");
  CHECK(d.split("train")[0].name == "images_2/img_1.png");
  std::vector<const View*> views = {&d.split("test")[0]};
  for (const auto& v : d.split("train")) views.push_back(&v);
  views.push_back(&d.split("test")[1]);

  double minNear = 1e9;
  for (auto b : bounds) minNear = std::min(minNear, b.x);
  const double s = 1.0 / (0.75 * minNear);
  glm::dvec3 centre(0), backSum(0), upSum(0);
  for (int i = 0; i < n; i++) {
    const Camera& c = views[i]->camera;
    CHECK(c.width == W);
    CHECK(c.height == H);
    CHECK(c.fx == doctest::Approx(focal / factor));
    CHECK(c.cy == 6.0);
    CHECK(views[i]->nearBound == doctest::Approx(bounds[i].x * s));
    CHECK(views[i]->farBound == doctest::Approx(bounds[i].y * s));
    CHECK(views[i]->image.at(3, 2, 1) == doctest::Approx(testValue(3, 2, 1, i)));
    // the loaded pose is the original one mapped by the normalisation
    glm::dmat4 expect = d.normalization * poses[i];
    for (int k = 0; k < 3; k++) expect[k] /= s;  // rotation columns are not scaled
    CHECK(maxDiff(c.cameraToWorld, expect) < 1e-9);
    centre += c.position();
    backSum += c.back();
    upSum += c.up();
    for (int j = 0; j < i; j++) {
      const Camera& o = views[j]->camera;
      // distances scale by s; relative rotations are kept
      CHECK(glm::length(c.position() - o.position()) ==
            doctest::Approx(s * glm::length(glm::dvec3(poses[i][3] - poses[j][3]))).epsilon(1e-9));
      glm::dmat3 relLoaded = glm::transpose(glm::dmat3(c.cameraToWorld)) * glm::dmat3(o.cameraToWorld);
      glm::dmat3 relOrig = glm::transpose(glm::dmat3(poses[i])) * glm::dmat3(poses[j]);
      CHECK(maxDiff(glm::dmat4(relLoaded), glm::dmat4(relOrig)) < 1e-9);
    }
  }
  // recentred: cameras' mean at the origin, mean back axis +Z, mean up in the YZ plane
  CHECK(glm::length(centre / double(n)) < 1e-9);
  CHECK(glm::length(glm::normalize(backSum) - glm::dvec3(0, 0, 1)) < 1e-9);
  CHECK(std::abs(upSum.x) < 1e-9);
  CHECK(upSum.y > 0);
}

TEST_CASE("bad LLFF datasets give one clear error each") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  std::vector<glm::dmat4> poses = {randomPose(rng), randomPose(rng)};
  std::vector<glm::dvec2> bounds = {{1, 5}, {1, 5}};
  for (int i = 0; i < 2; i++) writeImage(dir.str() + "/images/img_" + std::to_string(i) + ".png", testImage(10, 8, 3, i));
  auto expectError = [&](const NpyArray& a, const std::string& fragment) {
    writeNpy(dir.str() + "/poses_bounds.npy", a, true);
    std::string message = errorOf([&] { loadDataset(dir.str()); });
    INFO("error: '" << message << "', expected to mention '" << fragment << "'");
    CHECK(message.find(fragment) != std::string::npos);
  };
  NpyArray good = posesBounds(poses, bounds, 8, 10, 9);
  writeNpy(dir.str() + "/poses_bounds.npy", good, true);
  CHECK(loadDataset(dir.str()).split("train").size() == 1);
  NpyArray nan = good;
  nan.data[3] = std::numeric_limits<double>::quiet_NaN();
  expectError(nan, "non-finite");
  expectError(posesBounds(poses, bounds, 16, 20, 9), "the poses say 20x16");
  expectError(posesBounds({poses[0]}, {bounds[0]}, 8, 10, 9), "holds 2 images but");
  glm::dmat4 stretched = poses[1];
  stretched[2] *= 0.5;
  expectError(posesBounds({poses[0], stretched}, bounds, 8, 10, 9), "not orthonormal");
  expectError(posesBounds(poses, {{1, 5}, {0, 5}}, 8, 10, 9), "near <= far");
  NpyArray wrongShape = good;
  wrongShape.shape = {2, 17, 1};
  expectError(wrongShape, "N x 17");
  writeImage(dir.str() + "/images/img_1.png", testImage(9, 8, 3, 1));
  expectError(good, "expected 10x8");
}

TEST_CASE("scene bounds from cameras looking straight down: footprint, refracted box, depth, extent") {
  // two cameras 3 above the plane z = -1, looking straight down (back = +Z), 20x10 images
  auto downCamera = [](double x, double y, double z) {
    Camera c;
    c.cameraToWorld = glm::dmat4(1.0);
    c.cameraToWorld[3] = glm::dvec4(x, y, z, 1);
    c.width = 20;
    c.height = 10;
    c.fx = c.fy = 10;
    c.cx = 10;
    c.cy = 5;
    return c;
  };
  std::vector<Camera> cams = {downCamera(0, 0, 2), downCamera(4, 1, 2)};
  const double h = -1;  // footprint half-sizes: 3 * 10/10 = 3 in x, 3 * 5/10 = 1.5 in y
  Rect r = surfaceDomainFromCameras(cams, h, 0.0);
  CHECK(r.xMin == doctest::Approx(-3));
  CHECK(r.xMax == doctest::Approx(7));
  CHECK(r.yMin == doctest::Approx(-1.5));
  CHECK(r.yMax == doctest::Approx(2.5));
  Rect m = surfaceDomainFromCameras(cams, h, 0.1);
  CHECK(m.xMin == doctest::Approx(-4));
  CHECK(m.yMax == doctest::Approx(2.9));

  // corner ray of camera 1: direction (1, -0.5, -1)/|.|, sin(i) = |(1, .5)| / |(1, .5, 1)|
  const double ior = 1.33, depth = 2.0;
  Box b = gaussianBoxFromRefractedFrusta(cams, h, ior, depth);
  double sinI = std::sqrt(1.25) / std::sqrt(2.25), sinT = sinI / ior, tanT = sinT / std::sqrt(1 - sinT * sinT);
  double reach = depth * tanT;  // horizontal travel under water along the corner direction
  CHECK(b.max.x == doctest::Approx(7 + reach * 1.0 / std::sqrt(1.25)));
  CHECK(b.min.y == doctest::Approx(-1.5 - reach * 0.5 / std::sqrt(1.25)));
  CHECK(b.min.z == doctest::Approx(h - depth));
  CHECK(b.max.z == doctest::Approx(h));
  CHECK(reach < 3.0 * depth / 3.0);  // refraction narrows the frustum (the unrefracted reach would be depth)

  CHECK(sceneExtent(cams) == doctest::Approx(1.1 * std::sqrt(4.25)));

  std::vector<View> views(2);
  views[0].camera = cams[0];
  views[1].camera = cams[1];
  CHECK(estimateWaterDepth(views, h, ior) == doctest::Approx(3.0));  // no bounds: mean height above
  views[1].farBound = 5.0;                                            // 2 below the plane, apparent
  CHECK(estimateWaterDepth(views, h, ior) == doctest::Approx(ior * 2.0));

  // a camera that sees the horizon, or sits under the plane, is refused
  Camera tilted = downCamera(0, 0, 2);
  tilted.cameraToWorld = glm::dmat4(glm::mat3_cast(glm::angleAxis(1.3, glm::dvec3(1, 0, 0))));
  tilted.cameraToWorld[3] = glm::dvec4(0, 0, 2, 1);
  CHECK(errorOf([&] { surfaceDomainFromCameras({tilted}, h); }).find("horizon") != std::string::npos);
  CHECK(errorOf([&] { surfaceDomainFromCameras({downCamera(0, 0, -2)}, h); }).find("not above") != std::string::npos);
  CHECK_THROWS_AS(gaussianBoxFromRefractedFrusta(cams, h, ior, 0.0), Error);
  CHECK_THROWS_AS(sceneExtent({}), Error);
}

TEST_CASE("ground-truth height map named in water.json loads as a height grid") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  writeImage(dir.str() + "/a.png", testImage(8, 6, 3, 0));
  writeText(dir.path / "transforms_train.json", transformsJson("\"camera_angle_x\": 0.5", {{"a", randomPose(rng)}}));
  NpyArray h;
  h.shape = {3, 4};
  for (int i = 0; i < 12; i++) h.data.push_back(0.1 * i);
  writeNpy(dir.str() + "/gt_height.npy", h, true);
  writeText(dir.path / "water.json", R"({"domain": [-1, -1, 1, 1], "height_map": "gt_height.npy", "height_map_domain": [0, 0, 3, 2]})");
  auto g = loadGroundTruthSurface(loadDataset(dir.str()));
  REQUIRE(g.has_value());
  CHECK(g->nx == 4);
  CHECK(g->ny == 3);
  CHECK(g->xMax == 3.0);
  CHECK(sampleHeight(*g, 1.0, 1.0) == doctest::Approx(0.5));  // column 1, row 1: 0.1 * (4 + 1)
  CHECK(sampleHeight(*g, 1.5, 0.5) == doctest::Approx(0.5 * (0.15 + 0.55)));
  writeText(dir.path / "water.json", R"({"height_map": "gt_height.npy"})");
  CHECK(errorOf([&] { loadGroundTruthSurface(loadDataset(dir.str())); }).find("needs 'height_map_domain'") != std::string::npos);
  h.shape = {12};
  writeNpy(dir.str() + "/gt_height.npy", h, true);
  writeText(dir.path / "water.json", R"({"domain": [-1, -1, 1, 1], "height_map": "gt_height.npy"})");
  CHECK(errorOf([&] { loadGroundTruthSurface(loadDataset(dir.str())); }).find("2D array") != std::string::npos);
  writeText(dir.path / "water.json", R"({"ior": 1.2})");
  CHECK(!loadGroundTruthSurface(loadDataset(dir.str())).has_value());
}

TEST_CASE("refrax inspect loads a dataset and prints derived bounds, or one error line") {
  TempDir dir;
  glm::dmat4 down(1.0);  // looking straight down from z = 2
  down[3] = glm::dvec4(0.5, 0, 2, 1);
  glm::dmat4 down2 = down;
  down2[3] = glm::dvec4(-0.5, 0.2, 2.1, 1);
  writeImage(dir.str() + "/a.png", testImage(8, 6, 3, 0));
  writeImage(dir.str() + "/b.png", testImage(8, 6, 3, 1));
  writeText(dir.path / "transforms_train.json", transformsJson("\"camera_angle_x\": 0.8", {{"a", down}, {"b", down2}}));
  writeText(dir.path / "water.json", R"({"ior": 1.1, "height": 0.0})");
  auto r = test::runCli("inspect " + dir.str());
  INFO(r.output);
  CHECK(r.exitCode == 0);
  CHECK(r.output.find("train    2 views, 8x6") != std::string::npos);
  CHECK(r.output.find("surface domain") != std::string::npos);
  CHECK(r.output.find("initial Gaussian box") != std::string::npos);
  CHECK(r.output.find("ior 1.1000") != std::string::npos);
  auto over = test::runCli("inspect " + dir.str() + " --ior 1.33 --domain -1,-1,1,1");
  CHECK(over.output.find("ior 1.3300") != std::string::npos);
  CHECK(over.output.find("x [-1.0000, 1.0000]") != std::string::npos);
  auto bad = test::runCli("inspect " + dir.str() + " --domain 1,2,3");
  CHECK(bad.exitCode != 0);
  CHECK(bad.output.find("--domain expects four numbers") != std::string::npos);
  fs::remove(dir.path / "b.png");
  auto missing = test::runCli("inspect " + dir.str());
  CHECK(missing.exitCode != 0);
  CHECK(missing.output.find("/b does not exist (also tried .png") != std::string::npos);
  CHECK(std::count(missing.output.begin(), missing.output.end(), '\n') == 1);  // one line
}
