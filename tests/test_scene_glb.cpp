// `refrax export RUN --glb`: the Gaussians as KHR_gaussian_splatting in glTF axes (the same
// Gaussians: covariance and view-dependent colour turned with the axes) and the water as a
// refractive mesh, read back with tinygltf; bad input is one error. No device.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <tiny_gltf.h>

#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gltf_splats.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/model/scene_glb.h"
#include "engine/run/train_config.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

GaussianSet randomGlbGaussians(std::mt19937& rng, size_t n) {
  std::uniform_real_distribution<float> u(-1, 1);
  GaussianSet s;
  s.params.resize(n * kGaussianFloats);
  for (float& v : s.params) v = u(rng);
  for (size_t i = 0; i < n; i++) {
    float* p = s.at(i);
    p[f32::kGaussRotation] += 1.5f;  // away from a zero quaternion
    for (int a = 0; a < 3; a++) p[f32::kGaussLogScale + a] -= 2.0f;
  }
  return s;
}

// Σ from the extension's C = R(q) S (its formula written out, q = x y z w).
glm::dmat3 gltfCovariance(const float* q, const float* s) {
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  glm::dmat3 c;  // c[col][row]
  c[0] = double(s[0]) * glm::dvec3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y));
  c[1] = double(s[1]) * glm::dvec3(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x));
  c[2] = double(s[2]) * glm::dvec3(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
  return c * glm::transpose(c);
}

}  // namespace

TEST_CASE("glb export: each Gaussian's position, covariance, opacity and SH colour are the same Gaussian in glTF axes" *
          doctest::test_suite("one-backend")) {
  std::mt19937 rng(7);
  const GaussianSet set = randomGlbGaussians(rng, 50);
  const GltfSplats g = gltfSplatsFrom(set, 3);
  REQUIRE(g.count == 50);
  REQUIRE(g.sh.size() == 16);
  const glm::dmat3 axes(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));  // Refrax -> glTF: (x, y, z) -> (x, z, -y)
  std::uniform_real_distribution<double> u(-1, 1);
  double worstColour = 0, worstCovariance = 0;
  for (size_t i = 0; i < g.count; i++) {
    const float* p = set.at(i);
    const glm::dvec3 mean(p[0], p[1], p[2]);
    const glm::dvec3 pos(g.positions[3 * i], g.positions[3 * i + 1], g.positions[3 * i + 2]);
    CHECK(glm::length(pos - axes * mean) < 1e-6);
    // Σ in Refrax axes, turned, against the extension's Σ from what was written
    const glm::dmat3 r = f64::rotationOf(glm::dvec4(p[3], p[4], p[5], p[6]));
    const glm::dmat3 sd(glm::dvec3(std::exp(p[7]), 0, 0), glm::dvec3(0, std::exp(p[8]), 0), glm::dvec3(0, 0, std::exp(p[9])));
    const glm::dmat3 sigma = axes * (r * sd * sd * glm::transpose(r)) * glm::transpose(axes);
    const glm::dmat3 written = gltfCovariance(&g.rotations[4 * i], &g.scales[3 * i]);
    for (int c = 0; c < 3; c++) worstCovariance = std::max(worstCovariance, glm::length(sigma[c] - written[c]) / glm::length(sigma[c]));
    CHECK(std::abs(glm::length(glm::dvec4(g.rotations[4 * i], g.rotations[4 * i + 1], g.rotations[4 * i + 2], g.rotations[4 * i + 3])) - 1) < 1e-6);
    CHECK(g.opacities[i] == doctest::Approx(1 / (1 + std::exp(-double(p[10])))));
    // the colour seen along d in Refrax axes is the colour seen along the turned d
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    for (int ch = 0; ch < 3; ch++) {
      double before = 0, after = 0;
      for (uint32_t k = 0; k < 16; k++) {
        before += p[f32::kGaussSH + 3 * k + ch] * f64::shBasis(k, d);
        after += g.sh[k][3 * i + ch] * f64::shBasis(k, axes * d);
      }
      worstColour = std::max(worstColour, std::abs(before - after));
    }
  }
  MESSAGE("largest colour difference " << worstColour << ", relative covariance difference " << worstCovariance);
  CHECK(worstColour < 1e-5);
  CHECK(worstCovariance < 1e-5);
  CHECK_THROWS_AS(gltfSplatsFrom(set, 4), Error);
}

TEST_CASE("glb export: refrax export writes the splats and the refractive water, and refuses bad input with one error" *
          doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string run = dir / "run";
  std::filesystem::create_directories(run);
  TrainConfig c;
  c.model = WaterModel::Refraction;
  c.maxShDegree = 1;
  c.ior = 1.33;
  c.waterHeight = 0.1;
  c.boxMin[2] = -0.5;
  c.domain = {-1, -1, 1, 1};
  c.boxMax[0] = c.boxMax[1] = 1;
  resolveSchedule(c);
  writeJson(run + "/config.json", trainConfigToJson(c));
  std::mt19937 rng(3);
  writeGaussiansPly(run + "/point_cloud.ply", randomGlbGaussians(rng, 20));
  NpyArray heights;
  heights.shape = {3, 4};  // 3 rows along y, 4 columns along x
  for (int k = 0; k < 12; k++) heights.data.push_back(0.1 + 0.01 * k);
  writeNpy(run + "/water_height.npy", heights);

  const test::CliResult r = test::runCli("export " + run + " --glb " + dir / "scene.glb");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  tinygltf::Model m;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  REQUIRE(loader.LoadBinaryFromFile(&m, &err, &warn, dir / "scene.glb"));
  REQUIRE(m.meshes.size() == 2);
  const tinygltf::Primitive& splats = m.meshes[0].primitives[0];
  CHECK(splats.mode == TINYGLTF_MODE_POINTS);
  CHECK(splats.extensions.count("KHR_gaussian_splatting"));
  CHECK(splats.extensions.at("KHR_gaussian_splatting").Get("kernel").Get<std::string>() == "ellipse");
  for (const char* a : {"POSITION", "KHR_gaussian_splatting:ROTATION", "KHR_gaussian_splatting:SCALE", "KHR_gaussian_splatting:OPACITY",
                        "KHR_gaussian_splatting:SH_DEGREE_0_COEF_0", "KHR_gaussian_splatting:SH_DEGREE_1_COEF_2"}) {
    INFO(a);
    REQUIRE(splats.attributes.count(a));
    CHECK(m.accessors[size_t(splats.attributes.at(a))].count == 20);
  }
  CHECK(!splats.attributes.count("KHR_gaussian_splatting:SH_DEGREE_2_COEF_0"));  // the run's SH degree is 1
  const tinygltf::Primitive& water = m.meshes[1].primitives[0];
  CHECK(m.accessors[size_t(water.attributes.at("POSITION"))].count == 12);
  CHECK(m.accessors[size_t(water.indices)].count == 3 * 2 * 3 * 2);
  // the corner (x 1, y 1) holds the last height, 0.21, at glTF (1, 0.21, -1)
  const tinygltf::Accessor& pa = m.accessors[size_t(water.attributes.at("POSITION"))];
  CHECK(pa.maxValues[1] == doctest::Approx(0.21).epsilon(1e-6));
  const tinygltf::Material& mat = m.materials[size_t(water.material)];
  CHECK(mat.extensions.at("KHR_materials_ior").Get("ior").GetNumberAsDouble() == doctest::Approx(1.33));
  CHECK(mat.extensions.at("KHR_materials_volume").Get("thicknessFactor").GetNumberAsDouble() == doctest::Approx(0.6));
  CHECK(mat.extensions.count("KHR_materials_transmission"));

  const test::CliResult only = test::runCli("export " + run + " --glb " + dir / "splats.glb --splats-only");
  REQUIRE(only.exitCode == 0);
  tinygltf::Model s;
  REQUIRE(loader.LoadBinaryFromFile(&s, &err, &warn, dir / "splats.glb"));
  CHECK(s.meshes.size() == 1);

  // any 3DGS PLY: its Gaussians alone, at SH degree 3
  REQUIRE(test::runCli("export " + run + "/point_cloud.ply --glb " + dir / "ply.glb").exitCode == 0);
  tinygltf::Model p;
  REQUIRE(loader.LoadBinaryFromFile(&p, &err, &warn, dir / "ply.glb"));
  CHECK(p.meshes.size() == 1);
  CHECK(p.meshes[0].primitives[0].attributes.count("KHR_gaussian_splatting:SH_DEGREE_3_COEF_6"));

  test::checkOneError(test::runCli("export " + run), "--glb");
  test::checkOneError(test::runCli("export " + run + " --glb " + dir / "scene.gltf"), "must end in .glb");
  test::checkOneError(test::runCli("export " + dir / "nothing" + " --glb " + dir / "x.glb"), "nothing");
  std::filesystem::remove(run + "/water_height.npy");
  test::checkOneError(test::runCli("export " + run + " --glb " + dir / "y.glb"), "water_height.npy");
  CHECK(!std::filesystem::exists(dir / "x.glb"));
  CHECK(!std::filesystem::exists(dir / "y.glb"));
}

}  // namespace refrax
