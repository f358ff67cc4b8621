// The plane sweep (engine/train/plane_sweep.h) on hand-built views: pinhole cameras over a
// textured scene of two floors, seen straight and through flat water (rays refracted at
// z = 0 by Snell's law); the Gaussians drawn on its depth map; and --init-depth in a session.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/train/init_gaussians.h"
#include "engine/train/plane_sweep.h"
#include "engine/train/train_session.h"
#include "engine/vk/vk_buffer.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

// The scene: a floor at z = -0.4 for x < 0 and at z = -0.65 for x >= 0, a random colour per
// 6 cm square (or one grey when `textured` is false).
double floorZ(double x) { return x < 0 ? -0.4 : -0.65; }
void floorColour(double x, double y, bool textured, float rgb[3]) {
  uint32_t h = uint32_t(int32_t(std::floor(x / 0.06)) * 73856093) ^ uint32_t(int32_t(std::floor(y / 0.06)) * 19349663);
  for (int c = 0; c < 3; c++) {
    h = h * 1664525u + 1013904223u;
    rgb[c] = textured ? float((h >> 8) & 0xffff) / 65535.0f : 0.5f;
  }
}

// Pinhole cameras looking straight down from z = 1 on a 3 x 3 grid 0.3 m apart, 64 x 64
// pixels, 60 degrees across; with `ior` > 1 the rays are refracted into water whose surface
// is z = 0 and start there. Each ray's pixel gets the colour where it meets the scene.
struct Views {
  std::vector<Image> images;
  std::vector<SweepView> views;
};
Views makeViews(double ior, bool textured) {
  const int size = 64;
  const double focal = 0.5 * size / std::tan(M_PI / 6);
  Views out;
  out.images.resize(9);
  for (int cam = 0; cam < 9; cam++) {
    glm::dvec3 eye(0.3 * (cam % 3 - 1), 0.3 * (cam / 3 - 1), 1.0);
    Image& im = out.images[cam];
    im.width = im.height = size;
    im.channels = 3;
    im.pixels.assign(size_t(size) * size * 3, 0.0f);
    SweepView v;
    for (int py = 0; py < size; py++)
      for (int px = 0; px < size; px++) {
        glm::dvec3 o = eye, d = glm::normalize(glm::dvec3((px + 0.5 - 0.5 * size) / focal, (py + 0.5 - 0.5 * size) / focal, -1.0));
        if (ior > 1) {  // refract at z = 0 (normal +z): the transmitted direction by Snell's law
          o = eye + d * (eye.z / -d.z);
          double eta = 1.0 / ior, cosi = -d.z, k = 1 - eta * eta * (1 - cosi * cosi);
          d = glm::normalize(eta * d + (eta * cosi - std::sqrt(k)) * glm::dvec3(0, 0, 1));
        }
        // The first floor the ray meets (the step's wall is grey).
        float rgb[3] = {0.5f, 0.5f, 0.5f};
        glm::dvec3 p = o + d * ((-0.4 - o.z) / d.z);
        if (p.x < 0) {
          floorColour(p.x, p.y, textured, rgb);
        } else {
          p = o + d * ((-0.65 - o.z) / d.z);
          if (p.x >= 0) floorColour(p.x, p.y, textured, rgb);
        }
        size_t i = size_t(py) * size + px;
        for (int c = 0; c < 3; c++) im.pixels[3 * i + c] = rgb[c];
        GpuRay r{};
        for (int a = 0; a < 3; a++) r.origin[a] = float(o[a]), r.dir[a] = float(d[a]);
        r.tmax = 1e6f;
        v.rays.push_back(r);
      }
    out.views.push_back(std::move(v));
  }
  for (int cam = 0; cam < 9; cam++) out.views[cam].image = &out.images[cam];
  return out;
}

PlaneSweepConfig sweepBox() {
  PlaneSweepConfig c;
  c.xMin = c.yMin = -0.9;
  c.xMax = c.yMax = 0.9;
  c.zMin = -1.0;
  c.zMax = 0.0;
  c.planes = 100;  // 1 cm apart
  return c;
}

}  // namespace

TEST_CASE("plane sweep: the depth of a textured two-level floor, seen straight and through flat water") {
  for (double ior : {1.0, 1.33}) {
    CAPTURE(ior);
    Views v = makeViews(ior, true);
    DepthMap map = planeSweepDepth(v.views, sweepBox());
    REQUIRE(map.cellsX > 20);
    REQUIRE(map.z.size() == size_t(map.cellsX) * map.cellsY);
    // Cells every camera sees, away from the step: their depth is the true floor's, not the
    // apparent one (about 1/1.33 of the depth under the water).
    size_t cells = 0, found = 0, near = 0;
    double absSum = 0;
    for (uint32_t j = 0; j < map.cellsY; j++)
      for (uint32_t i = 0; i < map.cellsX; i++) {
        double x = map.xMin + (i + 0.5) * map.cellSize, y = map.yMin + (j + 0.5) * map.cellSize;
        if (std::abs(x) > 0.3 || std::abs(y) > 0.3 || std::abs(x) < 0.08) continue;
        cells++;
        double z = map.z[size_t(j) * map.cellsX + i];
        if (!std::isfinite(z)) continue;
        found++;
        near += std::abs(z - floorZ(x)) <= 0.03;
        absSum += std::abs(z - floorZ(x));
      }
    // Measured (deterministic, on the CPU): mean error 1.0 cm straight (every cell within 3 cm),
    // 1.75 cm through the water (83%): cells are 4-5 cm (two pixels), and the cameras' 0.3-0.6 m
    // baselines, narrower still under the water, move a cell's rays by a few millimetres per
    // centimetre of depth. The apparent depth under the water would be 10 or 16 cm off.
    double meanError = absSum / double(std::max<size_t>(1, found));
    MESSAGE("ior " << ior << ": " << found << " of " << cells << " cells with a depth, " << near << " within 3 cm, mean error " << meanError);
    REQUIRE(cells > 50);
    CHECK(found >= cells * 95 / 100);
    CHECK(near >= found * 75 / 100);
    CHECK(meanError <= 0.025);
  }
}

namespace {

// The sweep's cost table written directly, cell by cell: per plane, every (cell, view)'s colour
// sums, then each cell's spread of the views' mean colours summed over its whole window.
// planeSweepDepth computes the same from the cells each view reaches, window by rows and
// columns, planes on threads. cost[cell * planes + k], infinite where no window has a view.
std::vector<double> directSweepCosts(const std::vector<SweepView>& views, const PlaneSweepConfig& c, const DepthMap& map,
                                     std::vector<float>& colour) {
  const size_t X = map.cellsX, Y = map.cellsY, cells = X * Y, V = views.size(), P = c.planes;
  std::vector<double> cost(cells * P, std::numeric_limits<double>::infinity());
  colour.assign(cells * P * 3, 0.0f);
  for (size_t k = 0; k < P; k++) {
    const double z = c.zMin + (double(k) + 0.5) * (c.zMax - c.zMin) / double(P);
    std::vector<double> sums(cells * V * 4, 0.0), spread(cells, 0.0), dof(cells, 0.0);
    for (size_t v = 0; v < V; v++)
      for (size_t i = 0; i < views[v].rays.size(); i++) {
        const GpuRay& r = views[v].rays[i];
        if (!(r.dir[2] < 0) || !(r.origin[2] >= z)) continue;
        const double t = (z - r.origin[2]) / r.dir[2];
        const long cell = map.cellAt(r.origin[0] + t * r.dir[0], r.origin[1] + t * r.dir[1]);
        if (cell < 0) continue;
        for (int ch = 0; ch < 3; ch++) sums[(size_t(cell) * V + v) * 4 + ch] += views[v].image->pixels[i * 3 + ch];
        sums[(size_t(cell) * V + v) * 4 + 3] += 1;
      }
    for (size_t cell = 0; cell < cells; cell++) {
      double mean[3] = {0, 0, 0}, squares = 0, n = 0;
      for (size_t v = 0; v < V; v++) {
        const double* s = &sums[(cell * V + v) * 4];
        if (s[3] == 0) continue;
        for (int ch = 0; ch < 3; ch++) mean[ch] += s[ch] / s[3], squares += (s[ch] / s[3]) * (s[ch] / s[3]);
        n++;
      }
      if (n == 0) continue;
      for (int ch = 0; ch < 3; ch++) mean[ch] /= n, colour[(cell * P + k) * 3 + ch] = float(mean[ch]);
      if (n < c.minViews) continue;
      spread[cell] = std::max(0.0, squares - n * (mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]));
      dof[cell] = n - 1;
    }
    const long R = long(c.windowRadius);
    for (long cy = 0; cy < long(Y); cy++)
      for (long cx = 0; cx < long(X); cx++) {
        double s = 0, n = 0;
        for (long wy = cy - R; wy <= cy + R; wy++)
          for (long wx = cx - R; wx <= cx + R; wx++)
            if (wx >= 0 && wy >= 0 && wx < long(X) && wy < long(Y)) s += spread[size_t(wy) * X + size_t(wx)], n += dof[size_t(wy) * X + size_t(wx)];
        if (n > 0) cost[(size_t(cy) * X + size_t(cx)) * P + k] = s / n;
      }
  }
  return cost;
}

}  // namespace

TEST_CASE("plane sweep: the best cost and colour of every cell match the sweep written directly, for several windows") {
  Views v = makeViews(1.33, true);
  for (uint32_t radius : {0u, 1u, 2u, 4u}) {
    CAPTURE(radius);
    PlaneSweepConfig c = sweepBox();
    c.planes = 40;
    c.windowRadius = radius;
    c.minViews = radius == 4 ? 5 : 3;
    const DepthMap map = planeSweepDepth(v.views, c);
    c.cellSize = map.cellSize;
    std::vector<float> colour;
    const std::vector<double> cost = directSweepCosts(v.views, c, map, colour);
    const size_t P = c.planes;
    size_t withCost = 0, withDepth = 0, costOff = 0, colourOff = 0;
    for (size_t cell = 0; cell < map.bestCost.size(); cell++) {
      const double* cc = &cost[cell * P];
      const size_t finite = size_t(std::count_if(cc, cc + P, [](double x) { return std::isfinite(x); }));
      if (finite < P / 2) {  // too few planes saw it to compare them: no cost
        costOff += !std::isnan(map.bestCost[cell]);
        continue;
      }
      withCost++;
      const size_t best = size_t(std::min_element(cc, cc + P) - cc);
      costOff += !(std::abs(map.bestCost[cell] - cc[best]) <= 1e-12 * std::max(1.0, cc[best]));
      if (!std::isfinite(map.z[cell])) continue;
      withDepth++;
      for (int ch = 0; ch < 3; ch++) colourOff += !(std::abs(map.rgb[cell * 3 + ch] - colour[(cell * P + best) * 3 + ch]) <= 1e-6f);
    }
    MESSAGE("window radius " << radius << ": " << withCost << " cells with a cost, " << withDepth << " with a depth");
    CHECK(withCost > 500);
    CHECK(withDepth > 200);
    CHECK(costOff == 0);
    CHECK(colourOff == 0);
  }
}

TEST_CASE("plane sweep: views agree less through a wrong water than through the right one") {
  // The views of the floor through flat water, traced through the right water (flat) and
  // through a wrong one: each ray's direction tilted as a wavy surface would (up to 0.08 rad).
  Views v = makeViews(1.33, true);
  std::vector<SweepView> wrong = v.views;
  for (SweepView& w : wrong)
    for (GpuRay& r : w.rays) {
      const double x = r.origin[0], y = r.origin[1];
      r.dir[0] += float(0.08 * std::sin(40 * x + 3 * y));
      r.dir[1] += float(0.08 * std::cos(37 * y - 5 * x));
    }
  PlaneSweepConfig c = sweepBox();
  c.cellSize = sweepCellSize(v.views, -0.5);  // one grid for both
  DepthMap right = planeSweepDepth(v.views, c), bent = planeSweepDepth(wrong, c);
  REQUIRE(right.bestCost.size() == right.z.size());
  for (size_t k = 0; k < right.z.size(); k++)
    if (std::isfinite(right.z[k])) CHECK(std::isfinite(right.bestCost[k]));  // a depth comes with its cost
  SweepAgreement a = compareSweepCosts(bent, right), same = compareSweepCosts(right, right);
  // Measured (deterministic, on the CPU): the wrong water's mean best cost 3.7x the right one's
  // (1.0x with tilts of 0.01 rad: 5 mm at the floor, a tenth of a cell).
  MESSAGE("wrong water against right: " << a.cost << " / " << a.reference << " over " << a.cells << " cells");
  CHECK(a.cells > 500);
  CHECK(a.cost > 1.5 * a.reference);
  CHECK(same.cost == same.reference);
  // Cells compared are those both sweeps have a cost for; grids that differ are refused.
  DepthMap holes = right;
  for (size_t k = 0; k < holes.bestCost.size(); k += 2) holes.bestCost[k] = std::numeric_limits<double>::quiet_NaN();
  CHECK(compareSweepCosts(holes, right).cells < same.cells);
  DepthMap coarse = right;
  coarse.cellSize *= 2;
  CHECK_THROWS_WITH_AS(compareSweepCosts(coarse, right), doctest::Contains("grids differ"), Error);
}

TEST_CASE("plane sweep: a textureless floor has no depth, and bad input is one clear error") {
  Views v = makeViews(1.33, false);
  DepthMap map = planeSweepDepth(v.views, sweepBox());
  CHECK(std::none_of(map.z.begin(), map.z.end(), [](double z) { return std::isfinite(z); }));

  PlaneSweepConfig flat = sweepBox();
  flat.zMax = flat.zMin;
  CHECK_THROWS_WITH_AS(planeSweepDepth(v.views, flat), doctest::Contains("depth range"), Error);
  v.views[2].rays.pop_back();
  CHECK_THROWS_WITH_AS(planeSweepDepth(v.views, sweepBox()), doctest::Contains("do not match"), Error);
}

TEST_CASE("plane sweep: the Gaussians drawn on a depth map sit at its depth with its colour, elsewhere in the box") {
  DepthMap map;
  map.cellsX = 4;
  map.cellsY = 2;
  map.xMin = -1;
  map.yMin = -1;
  map.cellSize = 0.5;  // the map covers x in [-1, 1), y in [-1, 0)
  map.z.assign(8, std::nan(""));
  map.rgb.assign(24, 0.0f);
  map.z[1] = -0.3;  // x in [-0.5, 0), y in [-1, -0.5)
  map.rgb[3] = 0.9f, map.rgb[4] = 0.2f, map.rgb[5] = 0.4f;
  const double boxMin[3] = {-1, -1, -1}, boxMax[3] = {1, 1, 0};
  std::mt19937 rng(5);
  GaussianSet set = initialGaussiansOnDepth(rng, 4000, boxMin, boxMax, 0.1, map);
  REQUIRE(set.count() == 4000);
  size_t onMap = 0, elsewhere = 0, offDepth = 0;
  double minZ = 0, maxZ = -1;
  for (size_t i = 0; i < set.count(); i++) {
    const float* g = set.at(i);
    double x = g[f32::kGaussMean], y = g[f32::kGaussMean + 1], z = g[f32::kGaussMean + 2];
    REQUIRE(x >= -1);
    REQUIRE(x <= 1);
    REQUIRE(y >= -1);
    REQUIRE(y <= 1);
    if (x >= -0.5 && x < 0 && y < -0.5) {
      onMap++;
      offDepth += std::abs(z + 0.3) > 1e-6;
      const float rgb[3] = {0.9f, 0.2f, 0.4f};
      for (int c = 0; c < 3; c++) CHECK(std::abs(0.28209479177387814 * g[f32::kGaussSH + c] + 0.5 - rgb[c]) < 1e-5);
    } else {
      elsewhere++;
      minZ = std::min(minZ, z);
      maxZ = std::max(maxZ, z);
    }
  }
  CHECK(onMap > 180);  // 1/16 of the box's area: 250 expected
  CHECK(offDepth == 0);
  // Elsewhere uniform in the box's depth, as initialGaussians draws them.
  CHECK(elsewhere > 3000);
  CHECK(minZ < -0.95);
  CHECK(maxZ > -0.05);
}

GPU_TEST_CASE("plane sweep: --init-depth sweep draws the first Gaussians onto the scene, survives config.json, and is validated") {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 4, 2000, 16, 1, d);
  c.model = WaterModel::KnownWater;  // the sweep looks through the true water
  // The tiny preset's scene under the seen centre (|x|, |y| < 0.3) lies between the floor
  // (z = -0.52) and the sphere's top (-0.3).
  auto onScene = [](const GaussianSet& g) {
    size_t centre = 0, on = 0;
    for (size_t i = 0; i < g.count(); i++) {
      const float* p = g.at(i) + f32::kGaussMean;
      if (std::abs(p[0]) >= 0.3f || std::abs(p[1]) >= 0.3f) continue;
      centre++;
      on += p[2] > -0.55f && p[2] < -0.28f;
    }
    REQUIRE(centre > 100);
    return double(on) / double(centre);
  };
  auto box = createTrainSession(ctx, c, d);
  c.initDepth = InitDepth::Sweep;
  auto swept = createTrainSession(ctx, c, d);
  double fromBox = onScene(box->model.gaussians), fromSweep = onScene(swept->model.gaussians);
  // Measured on lavapipe: 0.98 swept (median 0.5 cm from the true top), about 0.27 drawn
  // uniformly in the box (the scene's 0.27 m of the box's 1 m).
  MESSAGE("on the scene: " << fromSweep << " swept, " << fromBox << " from the box; cells with a depth " << swept->log.sweptCellFraction);
  CHECK(fromSweep >= 0.9);
  CHECK(fromBox <= 0.5);
  CHECK(swept->log.sweptCellFraction > 0.2);
  trainStep(*swept);  // it trains

  CHECK(trainConfigToJson(c)["init_depth"] == "sweep");
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").initDepth == InitDepth::Sweep);
  nlohmann::json old = trainConfigToJson(c);
  old.erase("init_depth");
  CHECK(trainConfigFromJson(old, "test").initDepth == InitDepth::Box);
  old["init_depth"] = "sfm";
  CHECK_THROWS_WITH_AS(trainConfigFromJson(old, "test"), doctest::Contains("init_depth"), Error);
  c.initDepth = InitDepth(7);  // no name: refused naming the flag, as any value out of range
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--init-depth"), Error);
}

GPU_TEST_CASE("plane sweep: the learned water is compared with the flat start, and the surface is lifted back") {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 4, 500, 16, 1, d);
  auto ratioAt = [&](double initRange) {
    c.mlpInitRange = initRange;
    auto s = createTrainSession(ctx, c, d);
    const std::vector<float> before = downloadVector<float>(ctx, s->model.surface->gridHeights, s->model.surface->gridPointCount);
    SweepAgreement a = agreementWithFlatWater(*s);
    CHECK(downloadVector<float>(ctx, s->model.surface->gridHeights, s->model.surface->gridPointCount) == before);
    CHECK(a.cells > 100);
    return a.cost / a.reference;
  };
  // A height field started nearly flat (heights ~1e-6 m) reads as the flat water; one started
  // rough (the reference's 0.1 init range: heights of centimetres) is worse than flat.
  // Measured on lavapipe: 1.000 and 4.2.
  const double nearlyFlat = ratioAt(1e-7), rough = ratioAt(0.1);
  MESSAGE("sweep cost against the flat water's: " << nearlyFlat << " nearly flat, " << rough << " rough");
  CHECK(nearlyFlat == doctest::Approx(1.0).epsilon(0.01));
  CHECK(rough > 1.2);
}
