// `refrax align-poses` (trainer/cmd_align_poses.cpp): a synthetic dataset's cameras written as
// a COLMAP model in a frame of COLMAP's own align back onto the truth with no error, the
// aligned dataset loads with the true cameras, a bound exceeded exits non-zero, and bad
// inputs are one clear error.
#include <doctest/doctest.h>

#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/dataset/colmap_model.h"
#include "engine/dataset/dataset.h"
#include "engine/dataset/pose_alignment.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

// The truth's train and test views as a COLMAP model in `frame` (x_colmap = frame(x)), images
// under images/<split>/ as COLMAP names them; `turnDeg` turns the first camera about its
// own x axis (a pose error).
void writeAsColmap(const Dataset& d, const Similarity& frame, const fs::path& out, double turnDeg) {
  ColmapModel m;
  uint32_t id = 1;
  for (const char* split : {"train", "test"})
    for (const View& v : d.split(split)) {
      const Camera& c = v.camera;
      if (id == 1) m.cameras[1] = ColmapCamera{1, "PINHOLE", uint64_t(c.width), uint64_t(c.height), {c.fx, c.fy, c.cx, c.cy}};
      glm::dmat3 axes(frame.rotation * c.right(), -(frame.rotation * c.up()), -(frame.rotation * c.back()));  // OpenCV's
      if (id == 1) axes = axes * glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(turnDeg), glm::dvec3(1, 0, 0)));
      const glm::dmat3 worldToCamera = glm::transpose(axes);
      ColmapImage im;
      im.id = id++;
      im.cameraId = 1;
      im.q = colmapQuaternion(worldToCamera);
      im.t = -(worldToCamera * applySimilarity(frame, c.position()));
      im.name = std::string(split) + "/" + fs::path(v.name).filename().string() + ".png";
      fs::create_directories((out / "images" / im.name).parent_path());
      writePng((out / "images" / im.name).string(), v.image);
      m.images.push_back(im);
    }
  fs::create_directories(out / "sparse/0");
  writeColmapModel((out / "sparse/0").string(), m, true);
}

Similarity someFrame() {
  Similarity s;
  s.scale = 2.5;
  s.rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), 1.1, glm::normalize(glm::dvec3(0.3, -0.8, 0.5))));
  s.translation = {4.0, -1.5, 7.0};
  return s;
}

}  // namespace

TEST_CASE("align-poses: cameras in COLMAP's own frame align back onto the truth, and the aligned dataset loads" * doctest::test_suite("one-backend")) {
  const std::string truthDir = test::tinyDataset("desk", "--rim 0.75");
  const Dataset truth = loadDataset(truthDir);
  test::TrainTempDir dir;
  writeAsColmap(truth, someFrame(), dir.path / "colmap", 0);
  // A file COLMAP did not register counts against the registered fraction.
  writePng(dir / "colmap/images/train/extra.png", truth.split("train")[0].image);

  auto r = test::runCli("align-poses " + (dir / "colmap") + " " + truthDir + " -o " + (dir / "aligned") + " --max-rotation-error 0.001 --max-centre-error 1e-6");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const size_t views = truth.split("train").size() + truth.split("test").size();
  CHECK(r.output.find("registered " + std::to_string(views) + " of the " + std::to_string(views + 1) + " images") != std::string::npos);
  nlohmann::json a = readJson(dir / "aligned/alignment.json");
  CHECK(a["matched"] == views);
  CHECK(a["scale"].get<double>() == doctest::Approx(1 / 2.5));
  CHECK(a["rotation_error_deg_max"].get<double>() < 1e-4);
  CHECK(a["centre_error_max"].get<double>() < 1e-6);

  const Dataset aligned = loadDataset(dir / "aligned");
  CHECK(aligned.format == "blender");
  CHECK(aligned.water.domain.has_value());  // the truth's water.json came along
  CHECK(fileExists(dir / "aligned/water_gt_height.npy"));
  CHECK(fileExists(dir / "aligned/bottom_gt_height.npy"));
  CHECK(fileExists(dir / "aligned/bottom_gt_ortho.png"));
  for (const char* split : {"train", "test"}) {
    REQUIRE(aligned.split(split).size() == truth.split(split).size());
    for (size_t i = 0; i < truth.split(split).size(); i++) {
      const Camera &got = aligned.split(split)[i].camera, &want = truth.split(split)[i].camera;
      CHECK(glm::length(got.position() - want.position()) < 1e-6);
      CHECK(rotationAngleDeg(glm::dmat3(got.cameraToWorld), glm::dmat3(want.cameraToWorld)) < 1e-4);
      CHECK(got.fx == doctest::Approx(want.fx));
      CHECK(aligned.split(split)[i].image.pixels == truth.split(split)[i].image.pixels);
    }
  }
  CHECK(!aligned.splits.count("air"));  // COLMAP was not given the water-removal views
}

TEST_CASE("align-poses: a bound exceeded or a bad input is one clear error and a non-zero exit" * doctest::test_suite("one-backend")) {
  const std::string truthDir = test::tinyDataset("desk", "--rim 0.75");
  const Dataset truth = loadDataset(truthDir);
  test::TrainTempDir dir;
  writeAsColmap(truth, someFrame(), dir.path / "colmap", 2.0);
  const std::string colmap = dir / "colmap";

  auto turned = test::runCli("align-poses " + colmap + " " + truthDir + " --max-rotation-error 1");
  CHECK(turned.exitCode != 0);
  CHECK(turned.output.find("rotation error median 0.000 deg, max 2.000 deg") != std::string::npos);
  CHECK(turned.output.find("exceeds --max-rotation-error 1") != std::string::npos);
  CHECK(test::runCli("align-poses " + colmap + " " + truthDir + " --max-rotation-error 3").exitCode == 0);
  auto few = test::runCli("align-poses " + colmap + " " + truthDir + " --min-registered 1.01");
  CHECK(few.exitCode != 0);
  CHECK(few.output.find("under --min-registered 1.01") != std::string::npos);

  auto negative = test::runCli("align-poses " + colmap + " " + truthDir + " --max-centre-error -1");
  CHECK(negative.exitCode != 0);
  CHECK(negative.output.find("--max-centre-error must be a number >= 0, got '-1'") != std::string::npos);

  auto noModel = test::runCli("align-poses " + (dir / "nothing") + " " + truthDir);
  CHECK(noModel.exitCode != 0);
  CHECK(noModel.output.find("no COLMAP model in " + (dir / "nothing")) != std::string::npos);
  auto oneArg = test::runCli("align-poses " + colmap);
  CHECK(oneArg.exitCode != 0);
  CHECK(oneArg.output.find("expected <colmap-dataset> <truth-dataset>") != std::string::npos);
  // A truth whose views have other names: nothing to match.
  fs::create_directories(dir.path / "other");
  fs::copy(truthDir, dir.path / "other", fs::copy_options::recursive);
  fs::rename(dir.path / "other/train", dir.path / "other/views");
  std::string t = readFile(dir / "other/transforms_train.json");
  for (size_t p; (p = t.find("./train/")) != std::string::npos;) t.replace(p, 8, "./views/");
  writeTextAtomic(dir / "other/transforms_train.json", t);
  fs::remove_all(dir.path / "other/test");
  fs::remove(dir.path / "other/transforms_test.json");
  auto unmatched = test::runCli("align-poses " + colmap + " " + (dir / "other"));
  CHECK(unmatched.exitCode != 0);
  CHECK(unmatched.output.find("match a view of") != std::string::npos);
  CHECK(unmatched.output.find("unmatched: test/000") != std::string::npos);
  // The output folder is not written over.
  fs::create_directories(dir.path / "full");
  writeTextAtomic(dir / "full/keep.txt", "x");
  auto full = test::runCli("align-poses " + colmap + " " + truthDir + " -o " + (dir / "full"));
  CHECK(full.exitCode != 0);
  CHECK(full.output.find("-o " + (dir / "full") + " is not empty") != std::string::npos);
}
