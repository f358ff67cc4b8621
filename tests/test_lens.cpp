// The lens models (shaders/include/lens.glsl, engine/camera/lens.h) against COLMAP's own
// definitions of its camera models, written out here independently (as COLMAP's models.h
// computes them: the distortion added to the undistorted point u = x/z, v = y/z), so a sign or
// a swapped coefficient in the shared math fails; the inverse against the forward over whole
// images; a folding lens refused; the transforms.json fields.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "engine/camera/camera.h"
#include "engine/camera/lens.h"
#include "engine/dataset/dataset.h"
#include "engine/io/json_io.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

// COLMAP's CamToImg for the models with distortion, from the undistorted point (u, v) (x/z,
// y/z in OpenCV's camera frame): pixel coordinates.
glm::dvec2 colmapCamToImg(const std::string& model, const std::vector<double>& q, double u, double v) {
  double fx, fy, cx, cy;
  const double* k;
  const bool oneFocal = model == "SIMPLE_RADIAL" || model == "RADIAL" || model == "SIMPLE_RADIAL_FISHEYE" || model == "RADIAL_FISHEYE";
  if (oneFocal) fx = fy = q[0], cx = q[1], cy = q[2], k = &q[3];
  else fx = q[0], fy = q[1], cx = q[2], cy = q[3], k = &q[4];
  const double u2 = u * u, v2 = v * v, uv = u * v, r2 = u2 + v2;
  double du = 0, dv = 0;
  if (model == "SIMPLE_RADIAL" || model == "RADIAL") {
    const double radial = k[0] * r2 + (model == "RADIAL" ? k[1] * r2 * r2 : 0.0);
    du = u * radial, dv = v * radial;
  } else if (model == "OPENCV") {  // k1 k2 p1 p2
    const double radial = k[0] * r2 + k[1] * r2 * r2;
    du = u * radial + 2 * k[2] * uv + k[3] * (r2 + 2 * u2);
    dv = v * radial + 2 * k[3] * uv + k[2] * (r2 + 2 * v2);
  } else if (model == "FULL_OPENCV") {  // k1 k2 p1 p2 k3 k4 k5 k6
    const double r4 = r2 * r2, r6 = r4 * r2;
    const double radial = (1 + k[0] * r2 + k[1] * r4 + k[4] * r6) / (1 + k[5] * r2 + k[6] * r4 + k[7] * r6);
    du = u * radial + 2 * k[2] * uv + k[3] * (r2 + 2 * u2) - u;
    dv = v * radial + 2 * k[3] * uv + k[2] * (r2 + 2 * v2) - v;
  } else {  // the fisheyes: k1 (k2 (k3 k4))
    const double r = std::sqrt(r2), theta = std::atan(r), t2 = theta * theta;
    double poly = 1 + k[0] * t2;
    if (model != "SIMPLE_RADIAL_FISHEYE") poly += k[1] * t2 * t2;
    if (model == "OPENCV_FISHEYE") poly += k[2] * t2 * t2 * t2 + k[3] * t2 * t2 * t2 * t2;
    du = u * theta * poly / r - u, dv = v * theta * poly / r - v;
  }
  return {fx * (u + du) + cx, fy * (v + dv) + cy};
}

struct ModelCase {
  std::string model;
  std::vector<double> params;
};

// One of each model Refrax traces, with every coefficient non-zero and distinct, on a
// 160 x 120 image.
std::vector<ModelCase> modelCases() {
  return {{"SIMPLE_RADIAL", {110, 81, 59, -0.15}},
          {"RADIAL", {110, 81, 59, -0.23, 0.04}},
          {"OPENCV", {112, 108, 81, 59, -0.25, 0.05, 0.0021, -0.0017}},
          {"FULL_OPENCV", {112, 108, 81, 59, -0.25, 0.05, 0.0021, -0.0017, 0.011, 0.031, -0.007, 0.002}},
          {"OPENCV_FISHEYE", {62, 61, 81, 59, 0.031, -0.012, 0.0011, -0.0002}},  // corners 94 degrees off the axis
          {"SIMPLE_RADIAL_FISHEYE", {62, 81, 59, 0.034}},
          {"RADIAL_FISHEYE", {62, 81, 59, 0.033, -0.011}}};
}

Camera cameraOf(const ModelCase& m) {
  LensIntrinsics in = intrinsicsFromColmap(m.model, m.params, "test");
  Camera c;  // identity pose: right +X, up +Y, back +Z, so OpenCV's (x, y, z) is world (x, -y, -z)
  c.width = 160, c.height = 120;
  c.fx = in.fx, c.fy = in.fy, c.cx = in.cx, c.cy = in.cy;
  c.lens = in.lens;
  return c;
}

}  // namespace

TEST_CASE("lens: each COLMAP model projects as COLMAP defines it" * doctest::test_suite("one-backend")) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-0.6, 0.6);
  for (const ModelCase& m : modelCases()) {
    INFO(m.model);
    Camera c = cameraOf(m);
    CHECK(c.lens.distorts());
    double worst = 0;
    for (int i = 0; i < 500; i++) {
      const double u = U(rng), v = U(rng), depth = 0.5 + std::abs(U(rng)) * 4;
      glm::dvec2 uv;
      REQUIRE(c.project(glm::dvec3(u, -v, -1) * depth, uv));
      worst = std::max(worst, glm::length(uv - colmapCamToImg(m.model, m.params, u, v)));
    }
    CHECK(worst < 1e-9);  // pixels
  }
}

TEST_CASE("lens: the ray through each pixel projects back onto it, whole image, each model" * doctest::test_suite("one-backend")) {
  for (const ModelCase& m : modelCases()) {
    INFO(m.model);
    Camera c = cameraOf(m);
    REQUIRE_NOTHROW(checkLensCoversImage(c, "test"));
    double worst = 0;
    for (int y = 0; y <= c.height; y += 4)
      for (int x = 0; x <= c.width; x += 4) {
        glm::dvec3 d = c.rayDirection(x, y);
        CHECK(std::abs(glm::length(d) - 1) < 1e-12);
        glm::dvec2 uv;
        REQUIRE(c.project(c.position() + 3.0 * d, uv));
        worst = std::max(worst, glm::length(uv - glm::dvec2(x, y)));
      }
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("lens: a 180-degree equidistant fisheye's rim looks along the image plane" * doctest::test_suite("one-backend")) {
  // theta_d = theta: the image point r pixels from the centre is r / f radians off the axis, so
  // with f = (half diagonal) / (pi / 2) the corners look 90 degrees off the axis, where x/z does
  // not exist; the ray is still defined and projects back.
  Camera c;
  c.width = 200, c.height = 100;
  c.cx = 100, c.cy = 50;
  c.fx = c.fy = std::hypot(100.0, 50.0) / (M_PI / 2);
  c.lens = intrinsicsFromColmap("OPENCV_FISHEYE", {c.fx, c.fy, c.cx, c.cy, 0, 0, 0, 0}, "test").lens;
  REQUIRE_NOTHROW(checkLensCoversImage(c, "test"));
  glm::dvec3 corner = c.rayDirection(200, 100);  // OpenCV (x, y, z) = world (x, -y, -z)
  CHECK(std::abs(corner.z) < 1e-12);
  CHECK(std::abs(std::atan2(-corner.y, corner.x) - std::atan2(50.0, 100.0)) < 1e-12);
  glm::dvec3 edge = c.rayDirection(200, 50);
  CHECK(std::acos(-edge.z) == doctest::Approx(100.0 / c.fx).epsilon(1e-12));
  glm::dvec2 uv;
  REQUIRE(c.project(c.position() + corner, uv));
  CHECK(glm::length(uv - glm::dvec2(200, 100)) < 1e-9);
  // a point behind the camera is past the rim: not in the image
  CHECK_FALSE(c.sees(glm::dvec3(0.1, 0.1, 1.0)));
}

TEST_CASE("lens: a distortion that folds over inside the image is refused, naming the point" * doctest::test_suite("one-backend")) {
  // r_d = r (1 + k1 r^2) turns back at r = 1 / sqrt(-3 k1): for k1 = -0.5 at r = 0.82, a
  // distorted radius of 0.54; the image's corner is at 0.9 (f = 100, half diagonal 90 pixels).
  Camera c;
  c.width = 144, c.height = 108;
  c.cx = 72, c.cy = 54;
  c.fx = c.fy = 100;
  c.lens = intrinsicsFromColmap("SIMPLE_RADIAL", {100, 72, 54, -0.5}, "test").lens;
  CHECK_THROWS_WITH_AS(checkLensCoversImage(c, "cameras.txt: camera 3"), doctest::Contains("cameras.txt: camera 3"), Error);
  CHECK_THROWS_WITH_AS(checkLensCoversImage(c, "x"), doctest::Contains("folds over"), Error);
  // a milder lens on the same image is fine, and the points past its turn are not "seen"
  c.lens.radial[0] = -0.1;  // turns at r = 1.83, a distorted radius of 1.22
  CHECK_NOTHROW(checkLensCoversImage(c, "x"));
  c.lens.radial[0] = -0.5;
  glm::dvec2 uv;
  CHECK_FALSE(c.project(glm::dvec3(1.5, 0, -1), uv));  // r = 1.5: past the turn, imaged nowhere
  // a fisheye whose polynomial turns back inside the image
  c.lens = intrinsicsFromColmap("SIMPLE_RADIAL_FISHEYE", {50, 72, 54, -0.6}, "test").lens;
  c.fx = c.fy = 50;
  CHECK_THROWS_WITH_AS(checkLensCoversImage(c, "x"), doctest::Contains("fisheye"), Error);
}

TEST_CASE("lens: COLMAP models in and out, and the ones without a ray refused" * doctest::test_suite("one-backend")) {
  for (const ModelCase& m : modelCases()) {
    INFO(m.model);
    Camera c = cameraOf(m);
    std::vector<double> params;
    const std::string model = colmapModelOf(c, params);
    Camera back = cameraOf({model, params});
    CHECK(back.lens.kind == c.lens.kind);
    CHECK(back.lens.radial == c.lens.radial);
    CHECK(back.lens.extra == c.lens.extra);
    CHECK(back.fx == c.fx);
    CHECK(back.cy == c.cy);
  }
  CHECK(intrinsicsFromColmap("OPENCV", {50, 50, 32, 24, 0, 0, 0, 0}, "x").lens.kind == LensKind::Pinhole);
  CHECK_THROWS_WITH_AS(intrinsicsFromColmap("FOV", {50, 50, 32, 24, 0.9}, "cameras.bin"), doctest::Contains("image_undistorter"), Error);
  CHECK_THROWS_WITH_AS(intrinsicsFromColmap("THIN_PRISM_FISHEYE", std::vector<double>(12, 0.0), "x"), doctest::Contains("THIN_PRISM_FISHEYE"), Error);
  CHECK_THROWS_WITH_AS(intrinsicsFromColmap("OPENCV", {50, 50, 32, 24}, "x"), doctest::Contains("has 8 parameters, the file gives 4"), Error);
  CHECK_THROWS_WITH_AS(intrinsicsFromColmap("RADIAL", {50, 32, 24, NAN, 0}, "x"), doctest::Contains("not a finite"), Error);
}

TEST_CASE("lens: transforms.json fields (nerfstudio's)" * doctest::test_suite("one-backend")) {
  LensFields f;
  CHECK(lensFromTransformsFields(f, "x").kind == LensKind::Pinhole);
  f.k1 = -0.2, f.p2 = 0.001;
  Lens opencv = lensFromTransformsFields(f, "x");
  CHECK(opencv.kind == LensKind::RadialTangential);
  CHECK(opencv.radial[0] == -0.2);
  CHECK(opencv.extra[3] == 0.001);
  LensFields written = transformsFieldsOf(opencv);
  CHECK(written.cameraModel == "OPENCV");
  CHECK(written.p2 == 0.001);
  f.k4 = 0.01;
  CHECK_THROWS_WITH_AS(lensFromTransformsFields(f, "transforms.json: frame 2"), doctest::Contains("k4"), Error);
  f = {};
  f.cameraModel = "OPENCV_FISHEYE";
  f.k4 = 0.01;
  Lens fish = lensFromTransformsFields(f, "x");
  CHECK(fish.kind == LensKind::Fisheye);
  CHECK(fish.radial[3] == 0.01);
  CHECK(transformsFieldsOf(fish).cameraModel == "OPENCV_FISHEYE");
  f.p1 = 0.1;
  CHECK_THROWS_WITH_AS(lensFromTransformsFields(f, "x"), doctest::Contains("no tangential"), Error);
  f = {};
  f.cameraModel = "EQUIRECTANGULAR";
  CHECK_THROWS_WITH_AS(lensFromTransformsFields(f, "x"), doctest::Contains("EQUIRECTANGULAR"), Error);
}

TEST_CASE("lens: a transforms.json frame's lens is read, and a bad one is one error naming the file and frame" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = dir / "d";
  fs::copy(test::tinyDataset("nerfrac-primary-sine"), data, fs::copy_options::recursive);
  const std::string file = data + "/transforms_train.json";
  const nlohmann::json original = readJson(file);
  auto withFrame1 = [&](const nlohmann::json& fields) {
    nlohmann::json j = original;
    for (const auto& [k, v] : fields.items()) j["frames"][1][k] = v;
    writeJson(file, j);
  };
  withFrame1({{"camera_model", "OPENCV"}, {"k1", -0.1}, {"p1", 0.001}});
  Dataset d = loadDataset(data);
  CHECK(d.split("train")[0].camera.lens.kind == LensKind::Pinhole);
  CHECK(d.split("train")[1].camera.lens.kind == LensKind::RadialTangential);
  CHECK(d.split("train")[1].camera.lens.extra[2] == 0.001);
  withFrame1({{"camera_model", "EQUIRECTANGULAR"}});
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("transforms_train.json: frame 1: camera_model EQUIRECTANGULAR"), Error);
  withFrame1({{"camera_model", "OPENCV"}, {"k1", -3.0}});
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("transforms_train.json: frame 1: the radial-tangential (OpenCV) lens"), Error);
  withFrame1({{"camera_model", 7}});
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("'camera_model' must be a string"), Error);
}
