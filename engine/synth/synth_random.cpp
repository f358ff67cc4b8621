#include "engine/synth/synth_random.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/synth/synth_rim.h"
#include "engine/synth/synth_rng.h"

namespace refrax::synth {

namespace {

using R = RandomSceneRanges;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kSqrtE = 1.6487212707001282;  // sqrt(e), as a constant: no exp in the draw
// Every triangle over the water stays this far under the lowest trough (checkSceneBelowWater
// only asks for below; the margin keeps a grazing ray's root finder clear of the floor).
constexpr double kClearance = 0.02;
// The domain grows to cover every view's footprint on the mean water, up to this half-width:
// an oblique ring's upper image edge can reach several camera heights away, and a larger
// domain would spread the learned height field thin for rays that see little.
constexpr double kMaxDomainHalf = 2.5;

// Stream keys: one generator per attempt, so a redraw is a fresh, reproducible draw.
constexpr uint64_t kRandomSceneKey = 0x52414E444F4D5343ull;  // "RANDOMSC"

// Draws that use only the generator and exact IEEE operations (see the header).
struct Draw {
  SynthRng rng;
  double uniform(double lo, double hi) { return rng.uniform(lo, hi); }
  // An integer in [lo, hi], each equally likely.
  int integer(int lo, int hi) { return std::min(hi, lo + int(rng.uniform() * double(hi - lo + 1))); }
  bool chance(double p) { return rng.uniform() < p; }
  // Uniform in sqrt(x): between uniform and log-uniform, so that the small end of a range that
  // spans a factor of ten (slopes 0.08-0.75) is drawn about as often as the large end.
  double sqrtUniform(double lo, double hi) {
    double s = uniform(std::sqrt(lo), std::sqrt(hi));
    return std::clamp(s * s, lo, hi);
  }
};

// The floor's relief: two crossed sines, faded to zero (with zero slope) at +-half.
double reliefHeight(const RandomSceneParams& p, double x, double y) {
  const double half = p.domainHalf;
  if (std::abs(x) >= half || std::abs(y) >= half) return 0;
  const double c = std::cos(p.reliefDirectionDeg * kDeg), s = std::sin(p.reliefDirectionDeg * kDeg);
  const double k = 2 * kPi / p.reliefWavelength;
  const double u = c * x + s * y, v = -s * x + c * y;
  const double tx = x / half, ty = y / half;
  const double window = (1 - tx * tx) * (1 - tx * tx) * (1 - ty * ty) * (1 - ty * ty);
  return p.reliefAmplitude * 0.5 * (std::sin(k * u + p.reliefPhase[0]) + std::sin(k * v + p.reliefPhase[1])) * window;
}

glm::dvec3 floorNormal(const RandomSceneParams& p, double x, double y) {
  const double e = 1e-4;
  double hx = (reliefHeight(p, x + e, y) - reliefHeight(p, x - e, y)) / (2 * e);
  double hy = (reliefHeight(p, x, y + e) - reliefHeight(p, x, y - e)) / (2 * e);
  return glm::normalize(glm::dvec3(-hx, -hy, 1.0));
}

// The rig's cameras at the drawn size. Grid: n x n downward cameras, `baseline` x height apart,
// the test (and water-removal) view at the rig's centre: the centre camera held out for odd n,
// a camera between the middle four for even n. Ring: cameras at the drawn tilt looking at the
// middle of the water column under the centre (so that their sight lines cross the water near
// its centre even at 50 deg tilt over a deep floor), three test views half a step in azimuth
// off the training ones.
void placeCameras(const RandomSceneParams& p, int width, int height, std::vector<SynthCamera>& train, std::vector<SynthCamera>& test) {
  const double fov = p.fovDeg * kDeg;
  train.clear();
  test.clear();
  if (p.rig == RandomRig::Grid) {
    const int n = p.gridSide;
    const double spacing = p.baseline * p.cameraHeight;
    for (int row = 0; row < n; row++)
      for (int col = 0; col < n; col++) {
        if (n % 2 == 1 && row == n / 2 && col == n / 2) continue;  // the test view's place
        double x = (col - 0.5 * (n - 1)) * spacing, y = (0.5 * (n - 1) - row) * spacing;
        train.push_back(downwardCamera({x, y, p.cameraHeight}, width, height, fov));
      }
    test.push_back(downwardCamera({0, 0, p.cameraHeight}, width, height, fov));
  } else {
    const glm::dvec3 target(0, 0, -0.5 * p.floorDepth);
    const double radius = (p.cameraHeight + 0.5 * p.floorDepth) / std::cos(p.ringTiltDeg * kDeg);
    train = ringCameras(p.ringViews, p.ringTiltDeg, radius, p.ringAzimuthDeg, target, width, height, fov);
    // Three test views spread around the ring, each half a step between two training views
    // (three evenly spaced ones, 120 deg apart, would sit a sixth of a step from a training
    // view unless the count divides by 3).
    const double step = 360.0 / p.ringViews;
    for (int j = 0; j < 3; j++) {
      const int between = (j * p.ringViews + 1) / 3;  // the training view the test view follows
      auto one = ringCameras(1, p.ringTiltDeg, radius, p.ringAzimuthDeg + (between + 0.5) * step, target, width, height, fov);
      test.push_back(one.front());
    }
  }
}

// Where a view's border rays meet the mean water: the largest |x| or |y| (kMaxDomainHalf for
// a ray at or above the horizon).
double footprintHalf(const std::vector<SynthCamera>& cams) {
  double far = 0;
  for (const auto& c : cams) {
    const glm::dvec3 o = cameraCentre(c);
    for (int i = 0; i <= 8; i++)
      for (int side = 0; side < 4; side++) {
        double t = double(i) / 8;
        double px = side < 2 ? t * c.width : (side == 2 ? 0 : c.width), py = side < 2 ? (side == 0 ? 0 : c.height) : t * c.height;
        glm::dvec3 d = cameraRayDirection(c, px, py);
        if (d.z > -1e-3) return kMaxDomainHalf;
        glm::dvec3 q = o + (-o.z / d.z) * d;
        far = std::max(far, std::max(std::abs(q.x), std::abs(q.y)));
      }
  }
  return far;
}

bool seesPoint(const SynthCamera& c, const glm::dvec3& q) {
  glm::dvec4 pc = glm::inverse(c.cameraToWorld) * glm::dvec4(q, 1.0);
  if (pc.z >= 0) return false;
  double px = c.cx + c.fx * pc.x / -pc.z, py = c.cy - c.fy * pc.y / -pc.z;
  return px >= 0 && px <= c.width && py >= 0 && py <= c.height;
}

// The largest square +-h around the centre whose every point (an 11 x 11 lattice) some test
// view sees on the mean water, in steps of 2 % of the domain.
double testViewHalf(const std::vector<SynthCamera>& test, double domainHalf) {
  for (double h = domainHalf; h > 0.05; h -= 0.02 * domainHalf) {
    bool all = true;
    for (int j = 0; j <= 10 && all; j++)
      for (int i = 0; i <= 10 && all; i++) {
        glm::dvec3 q(-h + 2 * h * i / 10, -h + 2 * h * j / 10, 0);
        all = std::any_of(test.begin(), test.end(), [&](const SynthCamera& c) { return seesPoint(c, q); });
      }
    if (all) return h;
  }
  return 0.05;
}

RandomSceneParams drawOnce(uint64_t seed, int attempt) {
  Draw d{SynthRng(mixKeys(mixKeys(seed, kRandomSceneKey), uint64_t(attempt)))};
  RandomSceneParams p;
  p.seed = seed;
  p.redraws = attempt;
  p.ior = d.uniform(R::kMinIor, R::kMaxIor);

  // The rig first: the water's domain and where the objects go follow from what it sees.
  p.rig = d.chance(0.5) ? RandomRig::Grid : RandomRig::Ring;
  p.cameraHeight = d.uniform(R::kMinCameraHeight, R::kMaxCameraHeight);
  p.fovDeg = d.uniform(R::kMinFovDeg, R::kMaxFovDeg);
  p.width = d.integer(R::kMinWidth, R::kMaxWidth);
  if (p.rig == RandomRig::Grid) {
    p.height = p.width;  // square, as the NeRFrac-like rig
    p.gridSide = d.integer(R::kMinGridSide, R::kMaxGridSide);
    p.baseline = d.sqrtUniform(R::kMinBaseline, R::kMaxBaseline);
  } else {
    p.height = std::max(1, p.width * 3 / 4);  // 4:3, as the RefracGS-like rings
    p.ringViews = d.integer(R::kMinRingViews, R::kMaxRingViews);
    p.ringTiltDeg = d.uniform(R::kMinRingTiltDeg, R::kMaxRingTiltDeg);
    p.ringAzimuthDeg = d.uniform(0, 360);
  }
  p.floorDepth = d.uniform(R::kMinFloorDepth, R::kMaxFloorDepth);
  std::vector<SynthCamera> train, test;
  placeCameras(p, p.width, p.height, train, test);
  std::vector<SynthCamera> all = train;
  all.insert(all.end(), test.begin(), test.end());
  p.domainHalf = std::min(kMaxDomainHalf, std::max(0.5, 1.02 * footprintHalf(all)));
  p.testViewHalf = testViewHalf(test, p.domainHalf);

  // Water: 1-4 terms sharing the slope bound by random weights; each amplitude follows from
  // its share (a sine's slope is a k, a ripple's at most a (k + 1 / (sigma sqrt e))).
  const int terms = d.integer(R::kMinWaveComponents, R::kMaxWaveComponents);
  p.slopeBound = d.sqrtUniform(R::kMinSlopeBound, R::kMaxSlopeBound);
  std::vector<double> weights;
  double weightSum = 0;
  for (int i = 0; i < terms; i++) weightSum += weights.emplace_back(d.uniform(0.3, 1.0));
  const double centreRange = 0.5 * std::min(p.testViewHalf, p.domainHalf);
  for (int i = 0; i < terms; i++) {
    RandomWaveDraw w;
    w.ripple = d.chance(0.3);
    w.slopeShare = p.slopeBound * weights[i] / weightSum;
    w.phase = d.uniform(0, 2 * kPi);
    if (w.ripple) {
      w.wavelength = d.sqrtUniform(R::kMinRippleWavelength, R::kMaxRippleWavelength);
      w.sigma = d.uniform(R::kMinRippleSigma, R::kMaxRippleSigma);
      w.cx = d.uniform(-centreRange, centreRange);
      w.cy = d.uniform(-centreRange, centreRange);
      w.phase = 0;  // cos(k r) about the centre: the ripple has no phase (wave_surface.h)
      w.amplitude = w.slopeShare / (2 * kPi / w.wavelength + 1.0 / (w.sigma * kSqrtE));
    } else {
      w.wavelength = d.sqrtUniform(R::kMinSineWavelength, R::kMaxSineWavelength);
      w.directionDeg = d.uniform(0, 360);
      w.amplitude = w.slopeShare / (2 * kPi / w.wavelength);
    }
    p.heightBound += w.amplitude;
    p.waves.push_back(w);
  }

  // Floor: relief up to a quarter of the room between the floor and the lowest trough.
  const double room = p.floorDepth - p.heightBound - kClearance;
  p.reliefAmplitude = d.uniform(0.1, 0.25) * room;
  p.reliefWavelength = d.uniform(0.3, 1.2);
  p.reliefDirectionDeg = d.uniform(0, 360);
  p.reliefPhase[0] = d.uniform(0, 2 * kPi);
  p.reliefPhase[1] = d.uniform(0, 2 * kPi);
  p.floorTexture = d.integer(0, randomFloorTextureCount() - 1);
  p.floorRepeats = d.uniform(1, 4);  // coarse enough to read at 96 px (finer gravel turned to noise)
  for (double& t : p.floorTint) t = d.uniform(0.6, 1.0);

  // Objects inside what the test views see (and inside the rim's opening, drawn next), each
  // standing out of the floor's relief and topping out under the lowest trough.
  p.rim = d.chance(0.5);
  // The opening on a 1/256 m lattice: addSynthRim places its blocks at 1.5 a -+ 0.5 a, which for
  // such an a is exactly a, so no block's edge rounds into the water's domain (and fails
  // checkSceneBelowWater, as a = 0.7 did).
  if (p.rim) p.rimHalf = std::floor(d.uniform(R::kMinRimFraction, R::kMaxRimFraction) * p.domainHalf * 256) / 256;
  const double area = 0.7 * std::min(p.testViewHalf, p.rim ? p.rimHalf : p.domainHalf);
  const int objects = d.integer(R::kMinObjects, R::kMaxObjects);
  const int textures = int(randomSceneTextures().size());
  const double lowest = -p.floorDepth + p.reliefAmplitude + 0.02, highest = -p.heightBound - kClearance - 0.005;
  for (int i = 0; i < objects; i++) {
    RandomObjectDraw o;
    o.kind = RandomObjectKind(d.integer(0, 2));
    o.size = d.uniform(0.04, 0.18) * std::max(0.3, area);
    o.x = d.uniform(-area + o.size, area - o.size);
    o.y = d.uniform(-area + o.size, area - o.size);
    o.top = d.uniform(lowest, std::max(lowest, highest));
    o.yawDeg = d.uniform(0, 180);
    o.texture = d.integer(0, textures - 1);
    o.capTexture = d.integer(0, textures - 1);
    for (double& t : o.tint) t = d.uniform(0.6, 1.0);
    p.objects.push_back(o);
  }
  return p;
}

}  // namespace

const std::vector<std::string>& randomSceneTextures() {
  // The first four tile (floors); the rest are photographs (objects only).
  static const std::vector<std::string> stems = {"brick", "gravel", "grass", "text", "astronaut", "camera", "chelsea",
                                                 "clock", "coffee", "hubble_deep_field", "rocket"};
  return stems;
}

int randomFloorTextureCount() { return 4; }

std::string randomSceneProblem(const RandomSceneParams& p) {
  char why[160];
  const double trough = -p.heightBound;
  if (-p.floorDepth + p.reliefAmplitude >= trough - kClearance) {
    std::snprintf(why, sizeof why, "the floor's relief (top %.3f m) reaches the lowest trough (%.3f m)", -p.floorDepth + p.reliefAmplitude, trough);
    return why;
  }
  for (const auto& o : p.objects)
    if (o.top >= trough - kClearance) {
      std::snprintf(why, sizeof why, "an object (top %.3f m) reaches the lowest trough (%.3f m)", o.top, trough);
      return why;
    }
  return "";
}

RandomSceneParams drawRandomScene(uint64_t seed) {
  for (int attempt = 0; attempt < 64; attempt++) {
    RandomSceneParams p = drawOnce(seed, attempt);
    if (randomSceneProblem(p).empty()) return p;
  }
  // The ranges leave at least 0.2 m between the floor and the lowest trough: unreachable.
  fail("synth random: no scene of seed " + std::to_string(seed) + " fits under its water in 64 draws");
}

namespace {

// The drawn waves as the water's sines and ripples; returns the surface's description.
std::string randomWater(const RandomSceneParams& rp, WaveSurface& w) {
  w.meanHeight = 0;
  w.domain[0] = w.domain[1] = -rp.domainHalf;
  w.domain[2] = w.domain[3] = rp.domainHalf;
  int sines = 0, ripples = 0;
  for (const auto& t : rp.waves) {
    double k = 2 * kPi / t.wavelength;
    if (t.ripple) {
      w.ripples.push_back({t.amplitude, t.cx, t.cy, k, t.sigma});
      ripples++;
    } else {
      w.waves.push_back({t.amplitude, k * std::cos(t.directionDeg * kDeg), k * std::sin(t.directionDeg * kDeg), t.phase});
      sines++;
    }
  }
  char what[160];
  std::snprintf(what, sizeof what, "%d directional sine%s and %d radial ripple%s drawn at random (seed %llu), slope bound %.3f", sines,
                sines == 1 ? "" : "s", ripples, ripples == 1 ? "" : "s", (unsigned long long)rp.seed, rp.slopeBound);
  return what;
}

// The floor: the relief as one mesh with continuous UVs and smooth normals over the domain,
// a flat floor around and under it (just below the relief's lowest point, so no gap shows).
void addRandomFloor(const RandomSceneParams& rp, bool tiny, MaterialSet& mats, SceneBuilder& b) {
  const auto& stems = randomSceneTextures();
  const glm::dvec3 floorTint(rp.floorTint[0], rp.floorTint[1], rp.floorTint[2]);
  const int floorMat = mats.get(stems[rp.floorTexture], {rp.floorRepeats, rp.floorRepeats}, floorTint);
  const double L = rp.domainHalf, outer = L + 4;
  const double outerRepeats = rp.floorRepeats * outer / L;
  b.floorRect(-outer, -outer, outer, outer, -rp.floorDepth - rp.reliefAmplitude - 0.005,
              mats.get(stems[rp.floorTexture], {outerRepeats, outerRepeats}, floorTint));
  const int cells = tiny ? 16 : 48;
  auto vertex = [&](int i, int j, glm::dvec3& pos, glm::dvec3& n, glm::dvec2& uv) {
    double x = -L + 2 * L * i / cells, y = -L + 2 * L * j / cells;
    pos = {x, y, -rp.floorDepth + reliefHeight(rp, x, y)};
    n = floorNormal(rp, x, y);
    uv = {double(i) / cells, double(j) / cells};
  };
  for (int j = 0; j < cells; j++)
    for (int i = 0; i < cells; i++) {
      glm::dvec3 q[4], n[4];
      glm::dvec2 uv[4];
      vertex(i, j, q[0], n[0], uv[0]);
      vertex(i + 1, j, q[1], n[1], uv[1]);
      vertex(i + 1, j + 1, q[2], n[2], uv[2]);
      vertex(i, j + 1, q[3], n[3], uv[3]);
      for (int tri = 0; tri < 2; tri++) {
        const int idx[2][3] = {{0, 1, 2}, {0, 2, 3}};
        MeshTriangle t;
        for (int c = 0; c < 3; c++) {
          t.p[c] = q[idx[tri][c]];
          t.n[c] = n[idx[tri][c]];
          t.uv[c] = uv[idx[tri][c]];
        }
        t.material = floorMat;
        b.triangles.push_back(t);
      }
    }

}

// The objects, standing in the relief (their bases below its lowest point).
void addRandomObjects(const RandomSceneParams& rp, bool tiny, MaterialSet& mats, SceneBuilder& b) {
  const auto& stems = randomSceneTextures();
  const int seg = tiny ? 12 : 32;
  const double base = -rp.floorDepth - rp.reliefAmplitude;
  for (const auto& o : rp.objects) {
    const glm::dvec3 tint(o.tint[0], o.tint[1], o.tint[2]);
    const int mat = mats.get(stems[o.texture], {1, 1}, tint), cap = mats.get(stems[o.capTexture]);
    switch (o.kind) {
      case RandomObjectKind::Box:
        b.box({o.x, o.y, 0.5 * (o.top + base)}, {o.size, o.size, 0.5 * (o.top - base)}, o.yawDeg * kDeg, mat, cap);
        break;
      case RandomObjectKind::Sphere: b.sphere({o.x, o.y, o.top - o.size}, o.size, mat, seg); break;
      case RandomObjectKind::Cylinder: b.cylinder({o.x, o.y, base}, o.size, o.top - base, mat, seg, cap); break;
    }
  }
}

}  // namespace

SynthPreset buildRandomScene(const RandomSceneParams& rp, SynthSize size, const std::string& textureDir) {
  const bool tiny = size == SynthSize::Tiny;
  SynthPreset p;
  p.name = "random";
  p.ior = rp.ior;
  p.samplesPerAxis = 2;
  p.heightMapSize = tiny ? 64 : 512;
  p.meshGridSize = tiny ? 33 : 257;

  // Cameras at the drawn size, or capped for --size tiny (the field of view and aspect kept).
  int width = rp.width, height = rp.height;
  if (tiny && width > R::kTinyWidth) {
    height = std::max(1, int(std::lround(double(height) * R::kTinyWidth / width)));
    width = R::kTinyWidth;
  }
  placeCameras(rp, width, height, p.train, p.test);
  p.air = p.test;  // the water-removal views are the test cameras, as in the top-down presets

  p.surfaceDescription = randomWater(rp, p.water);
  MaterialSet mats{p.scene, textureDir, {}};
  SceneBuilder b;
  addRandomFloor(rp, tiny, mats, b);
  addRandomObjects(rp, tiny, mats, b);
  p.scene.bvh = buildTriangleBvh(std::move(b.triangles));

  char what[64];
  std::snprintf(what, sizeof what, "random scene (seed %llu): ", (unsigned long long)rp.seed);
  p.description = what + randomSceneSummary(rp);
  checkSceneBelowWater(p);  // the draw made sure (randomSceneProblem); this is the presets' rule
  if (rp.rim) addSynthRim(p, rp.rimHalf, textureDir);
  p.parametersJson = randomSceneJson(rp).dump(2);
  return p;
}

nlohmann::json randomSceneJson(const RandomSceneParams& p) {
  nlohmann::json waves = nlohmann::json::array(), objects = nlohmann::json::array();
  for (const auto& w : p.waves) {
    nlohmann::json j = {{"type", w.ripple ? "radial_ripple" : "directional_sine"}, {"slope_share", w.slopeShare}, {"amplitude", w.amplitude},
                        {"wavelength", w.wavelength}};
    if (w.ripple) {
      j["cx"] = w.cx;
      j["cy"] = w.cy;
      j["sigma"] = w.sigma;
    } else {
      j["direction_deg"] = w.directionDeg;
      j["phase"] = w.phase;
    }
    waves.push_back(j);
  }
  const char* kinds[] = {"box", "sphere", "cylinder"};
  for (const auto& o : p.objects)
    objects.push_back({{"kind", kinds[int(o.kind)]}, {"x", o.x}, {"y", o.y}, {"size", o.size}, {"top", o.top}, {"yaw_deg", o.yawDeg},
                       {"texture", randomSceneTextures()[o.texture]}, {"cap_texture", randomSceneTextures()[o.capTexture]},
                       {"tint", {o.tint[0], o.tint[1], o.tint[2]}}});
  int sines = 0, ripples = 0;
  for (const auto& w : p.waves) (w.ripple ? ripples : sines)++;
  nlohmann::json rig = {{"type", p.rig == RandomRig::Grid ? "grid" : "ring"}, {"camera_height", p.cameraHeight}, {"fov_deg", p.fovDeg},
                        {"width", p.width}, {"height", p.height}};
  if (p.rig == RandomRig::Grid) {
    rig["grid_side"] = p.gridSide;
    rig["baseline"] = p.baseline;
    rig["spacing"] = p.baseline * p.cameraHeight;
    rig["train_views"] = p.gridSide * p.gridSide - (p.gridSide % 2);
    rig["test_views"] = 1;
  } else {
    rig["ring_views"] = p.ringViews;
    rig["tilt_deg"] = p.ringTiltDeg;
    rig["azimuth_deg"] = p.ringAzimuthDeg;
    rig["train_views"] = p.ringViews;
    rig["test_views"] = 3;
  }
  return {{"generator", "refrax synth random"},
          {"seed", p.seed},
          {"redraws", p.redraws},
          {"summary", randomSceneSummary(p)},
          {"ior", p.ior},
          {"water", {{"sines", sines}, {"ripples", ripples}, {"slope_bound", p.slopeBound}, {"height_bound", p.heightBound}, {"terms", waves}}},
          {"rig", rig},
          {"domain_half", p.domainHalf},
          {"water_half", p.rim ? p.rimHalf : p.domainHalf},
          {"test_view_half", std::min(p.testViewHalf, p.rim ? p.rimHalf : p.domainHalf)},
          {"floor",
           {{"depth", p.floorDepth},
            {"relief_amplitude", p.reliefAmplitude},
            {"relief_wavelength", p.reliefWavelength},
            {"relief_direction_deg", p.reliefDirectionDeg},
            {"texture", randomSceneTextures()[p.floorTexture]},
            {"repeats", p.floorRepeats},
            {"tint", {p.floorTint[0], p.floorTint[1], p.floorTint[2]}}}},
          {"objects", objects},
          {"rim", p.rim},
          {"rim_half", p.rimHalf}};
}

std::string randomSceneSummary(const RandomSceneParams& p) {
  int sines = 0, ripples = 0;
  for (const auto& w : p.waves) (w.ripple ? ripples : sines)++;
  char rig[96], rest[224];
  if (p.rig == RandomRig::Grid)
    std::snprintf(rig, sizeof rig, "%d x %d top-down grid, baseline %.2f of the %.2f m camera height", p.gridSide, p.gridSide, p.baseline,
                  p.cameraHeight);
  else
    std::snprintf(rig, sizeof rig, "ring of %d views at %.1f deg tilt, %.2f m above the water", p.ringViews, p.ringTiltDeg, p.cameraHeight);
  std::snprintf(rest, sizeof rest, ", %d x %d px, %.0f deg field of view; water: %d sine%s + %d ripple%s, slope bound %.3f, IOR %.3f; "
                "floor %.2f m deep with %.1f cm relief, %zu object%s%s",
                p.width, p.height, p.fovDeg, sines, sines == 1 ? "" : "s", ripples, ripples == 1 ? "" : "s", p.slopeBound, p.ior, p.floorDepth,
                100 * p.reliefAmplitude, p.objects.size(), p.objects.size() == 1 ? "" : "s", p.rim ? "; dry rim" : "");
  return std::string(rig) + rest;
}

}  // namespace refrax::synth
