// nerfstudio datasets (one transforms.json as ns-process-data writes it): a synthetic truth
// written in an arbitrary frame with applied_transform, per-frame intrinsics, a mask_path,
// test_filenames and sparse_pc.ply loads with the water's frame derived as for COLMAP; bad
// split lists, masks and point clouds are one error naming the file.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/base/error.h"
#include "engine/dataset/dataset.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/ply_points.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

// x -> scale * rotation * x + shift: the source frame the truth is written in.
struct Similarity {
  glm::dmat3 rotation{1.0};
  double scale = 1;
  glm::dvec3 shift{0.0};
  glm::dvec3 apply(const glm::dvec3& p) const { return scale * (rotation * p) + shift; }
};

nlohmann::json rows(const glm::dmat4& m) {
  nlohmann::json r = nlohmann::json::array();
  for (int i = 0; i < 4; i++) r.push_back({m[0][i], m[1][i], m[2][i], m[3][i]});
  return r;
}

// The truth's train and test views as a nerfstudio dataset in `frame`: images/NNN.png, the
// first training view with a mask, the test views named by test_filenames, and sparse points
// on the floor and (a fifth of them) on a rim at the water height, as an ASCII sparse_pc.ply.
void writeAsNerfstudio(const Dataset& truth, const Similarity& frame, double waterHeight, const std::string& out) {
  fs::create_directories(out + "/images");
  fs::create_directories(out + "/masks");
  nlohmann::json top;
  top["camera_model"] = "OPENCV";
  top["fl_x"] = truth.split("train")[0].camera.fx;  // the file's; each frame repeats its own
  top["applied_transform"] = {{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, -1, 0}};
  top["ply_file_path"] = "sparse_pc.ply";
  nlohmann::json frames = nlohmann::json::array(), tests = nlohmann::json::array();
  int index = 0;
  for (const char* split : {"train", "test"})
    for (const View& v : truth.split(split)) {
      const Camera& c = v.camera;
      char name[32];
      std::snprintf(name, sizeof name, "images/%03d.png", index);
      writePng(out + "/" + name, v.image);
      glm::dmat4 pose(1.0);
      for (int a = 0; a < 3; a++) pose[a] = glm::dvec4(frame.rotation * glm::dvec3(c.cameraToWorld[a]), 0);
      pose[3] = glm::dvec4(frame.apply(c.position()), 1);
      nlohmann::json f = {{"file_path", name}, {"transform_matrix", rows(pose)}, {"fl_x", c.fx}, {"fl_y", c.fy}, {"cx", c.cx},
                          {"cy", c.cy},        {"w", c.width},                   {"h", c.height}, {"colmap_im_id", index + 1}};
      if (index == 0) {
        Image mask{c.width, c.height, 1, std::vector<float>(size_t(c.width) * c.height, 1.0f)};
        for (int x = 0; x < c.width / 4; x++) mask.at(x, 0, 0) = 0;
        writePng(out + "/masks/000.png", mask);
        f["mask_path"] = "masks/000.png";
      }
      if (std::string(split) == "test") tests.push_back(name);
      frames.push_back(f);
      index++;
    }
  top["frames"] = frames;
  top["test_filenames"] = tests;
  writeJson(out + "/transforms.json", top);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::ofstream ply(out + "/sparse_pc.ply");
  ply << "ply\nformat ascii 1.0\nelement vertex 200\nproperty float x\nproperty float y\nproperty float z\n"
         "property uint8 red\nproperty uint8 green\nproperty uint8 blue\nend_header\n";
  for (int i = 0; i < 200; i++) {
    const bool rim = i % 5 == 0;
    const glm::dvec3 p = frame.apply(glm::dvec3(u(rng), u(rng), rim ? waterHeight : waterHeight - 0.5 + 0.1 * u(rng)));
    ply << p.x << " " << p.y << " " << p.z << " 10 200 30\n";
  }
}

Similarity someFrame() {
  return {glm::dmat3(glm::rotate(glm::dmat4(1.0), 2.2, glm::normalize(glm::dvec3(-0.4, 0.7, 0.2)))), 3.5, glm::dvec3(-2.0, 5.0, 1.5)};
}

}  // namespace

TEST_CASE("nerfstudio dataset: transforms.json in its source's frame loads with the water's frame derived" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const Dataset truth = loadDataset(test::tinyDataset("nerfrac-primary-sine"));
  const double water = *truth.water.height;
  const std::string data = dir / "ns";
  writeAsNerfstudio(truth, someFrame(), water, data);
  const Dataset d = loadDataset(data);
  CHECK(d.format == "nerfstudio");
  REQUIRE(d.split("train").size() == truth.split("train").size());
  REQUIRE(d.split("test").size() == truth.split("test").size());
  std::vector<const View*> a, b;
  for (const char* split : {"train", "test"})
    for (size_t i = 0; i < truth.split(split).size(); i++) a.push_back(&truth.split(split)[i]), b.push_back(&d.split(split)[i]);
  // Up is the truth's +Z again (the rig looks straight down); distances scale by one factor.
  const double scale = glm::length(b[1]->camera.position() - b[0]->camera.position()) / glm::length(a[1]->camera.position() - a[0]->camera.position());
  for (size_t i = 0; i < a.size(); i++) {
    CHECK(b[i]->camera.back().z == doctest::Approx(a[i]->camera.back().z).epsilon(1e-9));
    CHECK(b[i]->camera.fx == a[i]->camera.fx);
    CHECK(b[i]->camera.lens.kind == LensKind::Pinhole);  // OPENCV with no coefficients
    for (size_t j = 0; j < i; j++)
      CHECK(glm::length(b[i]->camera.position() - b[j]->camera.position()) ==
            doctest::Approx(scale * glm::length(a[i]->camera.position() - a[j]->camera.position())).epsilon(1e-9));
  }
  // The water height from the rim's points: the truth's, relative to the cameras, scaled.
  double meanA = 0, meanB = 0;
  for (size_t i = 0; i < a.size(); i++) meanA += a[i]->camera.position().z / double(a.size()), meanB += b[i]->camera.position().z / double(a.size());
  REQUIRE(d.water.height);
  CHECK(meanB - *d.water.height == doctest::Approx(scale * (meanA - water)).epsilon(1e-6));
  CHECK(d.points.size() == 200);
  CHECK(d.points[0].colour.y == doctest::Approx(200 / 255.0));
  // The mask_path's mask on the first frame only.
  CHECK(d.split("train")[0].mask.width == a[0]->camera.width);
  CHECK(d.split("train")[0].mask.at(0, 0, 0) == 0);
  CHECK(d.split("train")[1].mask.pixels.empty());
  bool noted = false;
  for (const std::string& note : d.notes) noted = noted || note.find("applied_transform") != std::string::npos;
  CHECK(noted);
  // The CLI takes it, and its sparse points (--init-points).
  test::CliResult train = test::runCli("train " + data + " -o " + (dir / "run") + " --steps 4 --gaussians 200 --patch 16 --checkpoint-every 0 --init-points");
  INFO(train.output);
  CHECK(train.exitCode == 0);
  CHECK(train.output.find(" at sparse points)") != std::string::npos);
}

TEST_CASE("nerfstudio dataset: a bad split list, mask or point cloud is one error naming the file" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const Dataset truth = loadDataset(test::tinyDataset("nerfrac-primary-sine"));
  const std::string data = dir / "ns";
  writeAsNerfstudio(truth, someFrame(), *truth.water.height, data);
  const std::string file = data + "/transforms.json";
  const nlohmann::json original = readJson(file);
  auto edited = [&](auto edit) {
    nlohmann::json j = original;
    edit(j);
    writeJson(file, j);
  };
  edited([](nlohmann::json& j) { j["test_filenames"] = {"images/999.png"}; });
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("'test_filenames' names images/999.png"), Error);
  edited([](nlohmann::json& j) { j["train_filenames"] = j["test_filenames"]; });
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("is in both train_filenames and test_filenames"), Error);
  edited([](nlohmann::json& j) { j["frames"][1]["mask_path"] = "masks/none.png"; });
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("transforms.json: frame 1: image"), Error);
  edited([](nlohmann::json& j) { j["applied_transform"] = {1, 2, 3}; });
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("'applied_transform' must be a 3x4 or 4x4"), Error);
  edited([](nlohmann::json&) {});
  {
    std::string ply = readFile(data + "/sparse_pc.ply");
    writeFileAtomic(data + "/sparse_pc.ply", ply.data(), ply.size() / 2);
  }
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("sparse_pc.ply: point 97 has fewer values"), Error);
  // --test-views replaces the lists; --up is taken in the file's frame
  fs::remove(data + "/sparse_pc.ply");
  edited([](nlohmann::json& j) { j.erase("ply_file_path"); });
  DatasetOptions o;
  o.testViews = {"0", "3"};
  o.waterHeight = 0.0;
  Dataset d = loadDataset(data, o);
  CHECK(d.split("test").size() == 2);
  CHECK(d.points.empty());
}

TEST_CASE("PLY points: binary and ascii, any scalar type, colours optional" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string bin = dir / "p.ply";
  {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\nproperty float y\nproperty int16 z\nend_header\n";
    const double x[2] = {1.5, -2.25};
    const float y[2] = {3.0f, 4.5f};
    const int16_t z[2] = {-7, 9};
    for (int i = 0; i < 2; i++) {
      s.append(reinterpret_cast<const char*>(&x[i]), 8);
      s.append(reinterpret_cast<const char*>(&y[i]), 4);
      s.append(reinterpret_cast<const char*>(&z[i]), 2);
    }
    writeFileAtomic(bin, s.data(), s.size());
  }
  auto p = readPlyPoints(bin);
  REQUIRE(p.size() == 2);
  CHECK(p[1].position == glm::dvec3(-2.25, 4.5, 9));
  CHECK(p[0].colour == glm::dvec3(0.5));
  const std::string ascii = dir / "a.ply";
  const std::string text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n";
  writeFileAtomic(ascii, text.data(), text.size());
  CHECK_THROWS_WITH_AS(readPlyPoints(ascii), doctest::Contains("has no vertex property 'z'"), Error);
  const std::string nan = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 nan 2\n";
  writeFileAtomic(ascii, nan.data(), nan.size());
  CHECK_THROWS_AS(readPlyPoints(ascii), Error);
}
