// Built-in surfaces named on a command line (viewer and render --water): the fields parsed,
// the closed-form waves equal to the height function, one clear error for bad specs.
#include <doctest/doctest.h>

#include <random>

#include "engine/surface/builtin_surface_spec.h"
#include "engine/base/error.h"
#include "tests/gpu_test.h"

using namespace refrax;

TEST_CASE("built-in surface specs parse their fields and give the height function's waves") {
  BuiltinSurface b = parseBuiltinSurface("sine:0.25:0.05:0.7:30", -1.0f);
  CHECK(b.kind == "sine");
  CHECK(b.height == 0.25f);
  CHECK(b.amplitude == 0.05f);
  CHECK(b.wavelength == 0.7f);
  CHECK(b.directionDeg == 30.0f);
  BuiltinSurface flat = parseBuiltinSurface("flat", -1.5f);
  CHECK(flat.kind == "flat");
  CHECK(flat.height == -1.5f);  // the default height fills a missing field
  CHECK(parseBuiltinSurface("triangle:0:0.1", 0).amplitude == 0.1f);

  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (const char* spec : {"sine:0.25:0.05:0.7:30", "flat:-0.5", "sine:-1:0.1:0.3:135"}) {
    BuiltinSurface s = parseBuiltinSurface(spec, 0);
    AnalyticWaves w = builtinSurfaceWaves(s);
    auto h = surfaceHeightFunction(s);
    for (int i = 0; i < 100; i++) {
      float x = u(rng), y = u(rng);
      CHECK(analyticHeightRef(w, x, y) == doctest::Approx(h(x, y)).epsilon(1e-4));
    }
  }
}

TEST_CASE("bad built-in surface specs are one clear error") {
  CHECK_THROWS_WITH_AS(parseBuiltinSurface("lake", 0), doctest::Contains("unknown kind 'lake'"), refrax::Error);
  CHECK_THROWS_WITH_AS(parseBuiltinSurface("sine:x", 0), doctest::Contains("'x' is not a number"), refrax::Error);
  CHECK_THROWS_WITH_AS(parseBuiltinSurface("sine:0:0.1:0", 0), doctest::Contains("wavelength"), refrax::Error);
  CHECK_THROWS_WITH_AS(parseBuiltinSurface("sine:0:0.1:1:0:7", 0), doctest::Contains("KIND[:height"), refrax::Error);
  CHECK_THROWS_WITH_AS(builtinSurfaceWaves(parseBuiltinSurface("triangle", 0)), doctest::Contains("no closed-form"), refrax::Error);
}
