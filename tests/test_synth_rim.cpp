// `refrax synth --rim` (engine/synth/synth_rim.h): the water shrinks to the rim's opening, the
// rim is dry scene above the water, and something standing beside the water hides the water
// behind it from the camera (the renderer looks for the scene before the water).
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>

#include "engine/base/error.h"
#include "engine/synth/render_view.h"
#include "engine/synth/synth_presets.h"
#include "engine/synth/synth_rim.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;
using namespace refrax::synth;
namespace fs = std::filesystem;

namespace {

using test::textureDir;


RayResult straightDown(const SynthPreset& p, double x, double y) {
  return shadeCameraRay(p.scene, &p.water, p.ior, {x, y, 3.0}, {0, 0, -1});
}

}  // namespace

TEST_CASE("synth rim: the water shrinks to the opening and the rim around it is dry" * doctest::test_suite("one-backend")) {
  SynthPreset p = makeSynthPreset("desk", SynthSize::Tiny, 1, textureDir());
  const size_t before = p.scene.bvh.triangles.size();
  REQUIRE(p.water.domain[2] == 1.5);
  addSynthRim(p, 0.75, textureDir());
  CHECK(p.water.domain[0] == -0.75);
  CHECK(p.water.domain[1] == -0.75);
  CHECK(p.water.domain[2] == 0.75);
  CHECK(p.water.domain[3] == 0.75);
  CHECK(p.scene.bvh.triangles.size() == before + 8 * 12);  // eight blocks of six quads
  CHECK(p.description.find("dry textured rim") != std::string::npos);

  const double top = p.water.meanHeight + waveHeightBound(p.water) + kRimFreeboard;
  for (glm::dvec2 xy : {glm::dvec2(1.1, 0.0), glm::dvec2(-1.2, 1.3), glm::dvec2(0.2, -1.4)}) {
    RayResult r = straightDown(p, xy.x, xy.y);
    CHECK_FALSE(r.metWater);
    REQUIRE(r.hitScene);
    CHECK(r.scenePoint.z == doctest::Approx(top));
  }
  // Inside the opening the water is met and the pool floor seen under it, as before.
  RayResult wet = straightDown(p, 0.3, -0.4);
  CHECK(wet.metWater);
  REQUIRE(wet.hitScene);
  CHECK(wet.scenePoint.z < p.water.meanHeight - waveHeightBound(p.water));
  // Beyond the rim's outer edge the floor is seen dry.
  RayResult beyond = straightDown(p, 1.7, 0.0);
  CHECK_FALSE(beyond.metWater);
  CHECK(beyond.scenePoint.z < -0.7);
}

TEST_CASE("synth rim: a block beside the water hides the water behind it" * doctest::test_suite("one-backend")) {
  // Flat water at z = 0 over [-1, 1]^2, a grey block standing out of it at x in [1, 1.2]
  // (top at 0.1), a floor under the water. The ray starts beyond the block, under its top,
  // aimed at the water's centre: it meets the block's wall first.
  SynthScene scene;
  SynthTexture grey;
  grey.width = grey.height = 1;
  grey.rgb = {0.5f, 0.5f, 0.5f};
  scene.textures.push_back(grey);
  scene.materials.push_back({0, {1, 1}, {1, 1, 1}});
  SceneBuilder b;
  b.floorRect(-3, -3, 3, 3, -0.5, 0);
  b.box({1.1, 0, -0.2}, {0.1, 0.5, 0.3}, 0, 0);
  scene.bvh = buildTriangleBvh(std::move(b.triangles));
  WaveSurface flat;
  const glm::dvec3 o(1.3, 0, 0.05), d = glm::normalize(glm::dvec3(-1.3, 0, -0.05));

  RayResult hidden = shadeCameraRay(scene, &flat, 1.33, o, d);  // geometryAboveWater not set: the water is taken first
  CHECK(hidden.metWater);
  scene.geometryAboveWater = true;
  RayResult r = shadeCameraRay(scene, &flat, 1.33, o, d);
  CHECK_FALSE(r.metWater);
  REQUIRE(r.hitScene);
  CHECK(r.scenePoint.x == doctest::Approx(1.2));
  // A ray passing over the block still meets the water.
  CHECK(shadeCameraRay(scene, &flat, 1.33, {1.3, 0, 0.5}, glm::normalize(glm::dvec3(-1.3, 0, -0.5))).metWater);
}

TEST_CASE("synth rim: a bad opening or a camera inside the rim is one clear error" * doctest::test_suite("one-backend")) {
  SynthPreset p = makeSynthPreset("desk", SynthSize::Tiny, 1, textureDir());
  CHECK_THROWS_WITH_AS(addSynthRim(p, 0, textureDir()), doctest::Contains("--rim must be a half-width in (0, 1.5] m"), Error);
  CHECK_THROWS_WITH_AS(addSynthRim(p, 1.6, textureDir()), doctest::Contains("--rim must be"), Error);
  CHECK_THROWS_WITH_AS(addSynthRim(p, std::nan(""), textureDir()), doctest::Contains("--rim must be"), Error);
  p.air[0].cameraToWorld[3] = glm::dvec4(1.2, 0.3, 0.0, 1.0);
  CHECK_THROWS_WITH_AS(addSynthRim(p, 0.75, textureDir()), doctest::Contains("inside the rim"), Error);

  test::TrainTempDir dir;
  auto r = test::runCli("synth desk --size tiny --rim 0 -o " + (dir / "x"));
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("--rim must be a half-width") != std::string::npos);
  CHECK(!fs::exists(dir.path / "x"));
}
