// Snell's law as the surface stage applies it: the shared vector form (CPU f64 and f32)
// against the scalar law and coplanarity, up to grazing incidence; back-facing normals and
// an IOR below 1 stay finite; its backward against central differences; and the shader
// path (the surface stage on a flat surface) against the scalar law.
#include <cmath>

#include "engine/surface/surface_math.h"
#include "tests/gpu_test.h"
#include "tests/surface_test_util.h"

using namespace refrax;
using glm::dvec3;

namespace {

dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> N(0, 1);
  dvec3 v(N(rng), N(rng), N(rng));
  return glm::normalize(v);
}

// A unit direction at incidence angle theta to -n (theta in [0, pi/2)).
dvec3 incidentAt(std::mt19937& rng, const dvec3& n, double theta) {
  dvec3 t = glm::normalize(glm::cross(n, randomUnit(rng)));
  return glm::normalize(-std::cos(theta) * n + std::sin(theta) * t);
}

double angleBetween(const dvec3& a, const dvec3& b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

}  // namespace

TEST_CASE("vector Snell obeys the scalar law and coplanarity up to grazing (f64 and f32)") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(0, 1);
  double worst64 = 0, worst32 = 0, worstPlane = 0;
  for (int k = 0; k < 20000; k++) {
    double ior = 1.0 + 0.6 * U(rng), eta = 1.0 / ior;
    dvec3 n = randomUnit(rng);
    // angles up to grazing, with a share right at it
    double theta = k % 10 == 0 ? (M_PI / 2) * (1 - 1e-7 * U(rng)) : (M_PI / 2) * U(rng);
    dvec3 d = incidentAt(rng, n, theta);
    dvec3 w = f64::snellRefract(d, n, eta);
    double theta2 = angleBetween(w, -n);
    worst64 = std::max(worst64, std::abs(std::sin(theta) - ior * std::sin(theta2)));
    worstPlane = std::max(worstPlane, std::abs(glm::dot(w, glm::cross(d, n))));
    REQUIRE(std::abs(glm::length(w) - 1) < 1e-12);
    REQUIRE(glm::dot(w, n) < 0);  // into the water
    // The float version against the double one at the same, float-rounded, inputs: near
    // grazing with an IOR near 1 the refracted ray itself turns by about 1e-5 for a rounding
    // of eta (cos theta_t ~ sqrt(1 - eta^2) is small), which is not the float code's error.
    const glm::vec3 d32(d), n32(n);
    const float eta32 = float(eta);
    glm::vec3 w32 = f32::snellRefract(d32, n32, eta32);
    dvec3 wAtFloatInputs = f64::snellRefract(dvec3(d32), dvec3(n32), double(eta32));
    worst32 = std::max(worst32, glm::length(glm::dvec3(w32) - wAtFloatInputs));
  }
  CHECK(worst64 < 1e-12);
  CHECK(worstPlane < 1e-12);
  CHECK(worst32 < 1e-5);
}

TEST_CASE("Snell's law stays finite for back-facing normals and an IOR below 1") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 2000; k++) {
    dvec3 n = randomUnit(rng);
    dvec3 d = incidentAt(rng, n, (M_PI / 2) * U(rng));
    // back-facing: the normal points along the ray; flipping it gives the front-facing result
    double s = f64::snellFacingSign(d, -n);
    REQUIRE(s == -1.0);
    dvec3 wFlipped = f64::snellRefract(d, s * -n, 0.75);
    REQUIRE(glm::length(wFlipped - f64::snellRefract(d, n, 0.75)) == 0.0);
    // eta > 1 (IOR below 1): beyond the critical angle the radicand is clamped at 0
    double eta = 1.0 + U(rng);
    dvec3 w = f64::snellRefract(d, n, eta);
    dvec3 gd, gn;
    f64::snellRefractBackward(d, n, eta, randomUnit(rng), gd, gn);
    REQUIRE(std::isfinite(w.x + w.y + w.z));
    REQUIRE(std::isfinite(gd.x + gd.y + gd.z + gn.x + gn.y + gn.z));
    glm::vec3 gd32, gn32;
    f32::snellRefractBackward(glm::vec3(d), glm::vec3(n), float(eta), glm::vec3(randomUnit(rng)), gd32, gn32);
    REQUIRE(std::isfinite(gd32.x + gd32.y + gd32.z + gn32.x + gn32.y + gn32.z));
  }
}

TEST_CASE("Snell backward matches central differences") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(0, 1);
  double worst = 0;
  for (int k = 0; k < 500; k++) {
    dvec3 n = randomUnit(rng);
    dvec3 d = incidentAt(rng, n, 1.5 * U(rng));
    double eta = 1 / (1.1 + 0.5 * U(rng));
    dvec3 g = randomUnit(rng);
    dvec3 gd, gn;
    f64::snellRefractBackward(d, n, eta, g, gd, gn);
    const double h = 1e-6;
    for (int a = 0; a < 3; a++) {
      dvec3 e(0);
      e[a] = h;
      double fdN = (glm::dot(g, f64::snellRefract(d, n + e, eta)) - glm::dot(g, f64::snellRefract(d, n - e, eta))) / (2 * h);
      double fdD = (glm::dot(g, f64::snellRefract(d + e, n, eta)) - glm::dot(g, f64::snellRefract(d - e, n, eta))) / (2 * h);
      worst = std::max({worst, std::abs(fdN - gn[a]), std::abs(fdD - gd[a])});
    }
  }
  CHECK(worst < 1e-7);
}

GPU_TEST_CASE("the surface shader refracts by the scalar law on a flat surface, up to grazing") {
  AnalyticWaves flat;
  flat.base = 0.05f;
  AnalyticHeightField field = createAnalyticHeightField(ctx, flat);
  HeightSource hs = heightSource(field);
  WaterSurfaceConfig cfg;
  cfg.gridCells = 8;
  cfg.subdivisionLevels = 1;
  std::uniform_real_distribution<double> U(0, 1);
  cfg.ior = float(1.1 + 0.4 * U(rng));
  cfg.maxRays = 4000;
  cfg.keepHitNormals = true;
  WaterSurface ws = createWaterSurface(ctx, cfg);
  test::updateSurface(ctx, ws, hs);
  // rays at random incidence up to 89.9 degrees aimed at points of the domain
  std::vector<GpuRay> rays(cfg.maxRays);
  for (auto& r : rays) {
    double theta = std::min(M_PI / 2 * U(rng), 89.9 * M_PI / 180);
    double phi = 2 * M_PI * U(rng);
    dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta));
    dvec3 target(1.8 * U(rng) - 0.9, 1.8 * U(rng) - 0.9, flat.base);
    dvec3 o = target - 0.5 * d;
    for (int a = 0; a < 3; a++) {
      r.origin[a] = float(o[a]);
      r.dir[a] = float(d[a]);
    }
    r.tmin = 0;
    r.tmax = 10;
  }
  auto run = test::runSurface(ctx, ws, hs, rays);
  size_t hits = 0;
  double worst = 0, worstPlane = 0;
  for (size_t i = 0; i < rays.size(); i++) {
    if (!(surfaceRecordFlags(run.recordList[i]) & kSurfaceHit)) continue;
    hits++;
    dvec3 d = glm::normalize(test::vec3Of(rays[i].dir)), w = test::vec3Of(run.refractedRays[i].dir);
    dvec3 n = test::vec3Of(&run.hitNormals[16 * i]);
    REQUIRE(std::abs(n.z - 1) < 1e-6);  // flat: the normal is up and faces the ray
    double theta1 = angleBetween(-d, n), theta2 = angleBetween(w, -n);
    worst = std::max(worst, std::abs(std::sin(theta1) - cfg.ior * std::sin(theta2)));
    worstPlane = std::max(worstPlane, std::abs(glm::dot(w, glm::cross(d, n))));
    REQUIRE(std::abs(run.refractedRays[i].origin[2] - flat.base) < 1e-5);
  }
  CHECK(hits > rays.size() * 9 / 10);
  CHECK(worst < 2e-6);
  CHECK(worstPlane < 2e-6);
}
