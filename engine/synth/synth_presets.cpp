#include "engine/synth/synth_presets.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/synth/synth_rng.h"

namespace refrax::synth {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// A stable name hash (std::hash may differ between standard libraries).
uint64_t fnv1a(const std::string& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

struct PresetEntry {
  std::string name;
  std::string family;  // "nerfrac" or the RefracGS-like scene
  bool topdown;
};

const std::vector<PresetEntry>& presetTable() {
  static const std::vector<PresetEntry> table = {
      {"nerfrac-primary-sine", "nerfrac", true}, {"nerfrac-second-sine", "nerfrac", true}, {"nerfrac-hybrid", "nerfrac", true},
      {"desk", "desk", false},                   {"kitchen", "kitchen", false},           {"toys", "toys", false},
      {"desk-topdown", "desk", true},            {"kitchen-topdown", "kitchen", true},    {"toys-topdown", "toys", true},
  };
  return table;
}

DirectionalWave sineAlong(double amplitude, double wavelength, double directionDeg, double phase) {
  double k = 2 * kPi / wavelength;
  return {amplitude, k * std::cos(directionDeg * kDeg), k * std::sin(directionDeg * kDeg), phase};
}

// ---- NeRFrac-like: a pool floor 0.5 under the water with a picture and a few objects.
void buildNerfracScene(SynthPreset& p, MaterialSet& mats, bool tiny) {
  int seg = tiny ? 12 : 48;
  SceneBuilder b;
  b.floorRect(-4, -4, 4, 4, -0.52, mats.get("brick", {16, 16}));
  b.box({0, 0, -0.51}, {0.6, 0.6, 0.01}, 0, mats.get("gravel"), mats.get("astronaut"));
  b.box({0.28, 0.22, -0.44}, {0.09, 0.07, 0.06}, 0.4, mats.get("coffee"));
  b.sphere({-0.25, -0.2, -0.4}, 0.1, mats.get("chelsea", {2, 1}), seg);
  b.cylinder({0.22, -0.28, -0.5}, 0.06, 0.14, mats.get("rocket", {2, 1}), seg, mats.get("clock"));
  if (!tiny) {
    b.box({-0.3, 0.3, -0.47}, {0.06, 0.06, 0.03}, -0.3, mats.get("camera"));
    b.sphere({0.0, 0.38, -0.45}, 0.05, mats.get("hubble_deep_field"), seg);
  }
  p.scene.bvh = buildTriangleBvh(std::move(b.triangles));
}

void setNerfracWater(SynthPreset& p, const std::string& name, SynthRng& rng) {
  WaveSurface& w = p.water;
  w.meanHeight = 0;
  w.domain[0] = w.domain[1] = -1;
  w.domain[2] = w.domain[3] = 1;
  auto phase = [&] { return 2 * kPi * rng.uniform(); };
  if (name == "nerfrac-primary-sine") {
    w.waves = {sineAlong(0.025, 0.5, 30, phase())};
    p.surfaceDescription = "one directional sine";
  } else if (name == "nerfrac-second-sine") {
    w.waves = {sineAlong(0.02, 0.5, 0, phase()), sineAlong(0.015, 0.35, 90, phase())};
    p.surfaceDescription = "two crossed directional sines";
  } else {
    w.waves = {sineAlong(0.02, 0.6, 20, phase())};
    w.ripples = {{0.02, 0.1, -0.05, 2 * kPi / 0.2, 0.35}};
    p.surfaceDescription = "a directional sine plus a radial ripple";
  }
}

// ---- RefracGS-like: 1.5 m x 1.5 m pool, floor 0.7 under the water, objects up to 0.45 tall.
void buildRefracgsScene(SynthPreset& p, MaterialSet& mats, const std::string& family, bool tiny) {
  int seg = tiny ? 12 : 48;
  SceneBuilder b;
  b.floorRect(-6, -6, 6, 6, -0.72, mats.get("gravel", {24, 24}, {0.85, 0.78, 0.62}));  // sand
  if (family == "desk") {
    b.box({0, 0, -0.71}, {0.75, 0.75, 0.01}, 0, mats.get("brick"), mats.get("brick", {3, 3}, {0.95, 0.6, 0.45}));
    b.box({0.05, 0.1, -0.55}, {0.45, 0.3, 0.15}, 0.1, mats.get("camera", {1, 1}, {0.8, 0.65, 0.45}), mats.get("text", {1, 1}, {1.0, 0.95, 0.8}));
    b.cylinder({0.3, 0.2, -0.4}, 0.05, 0.12, mats.get("coffee", {2, 1}), seg, mats.get("clock"));
    b.sphere({-0.2, 0.05, -0.3}, 0.1, mats.get("hubble_deep_field"), seg);
    b.box({0.0, -0.05, -0.38}, {0.12, 0.09, 0.02}, -0.3, mats.get("gravel"), mats.get("astronaut"));
    if (!tiny) {
      b.box({-0.5, -0.5, -0.6}, {0.12, 0.12, 0.1}, 0.5, mats.get("chelsea"));
      b.cylinder({0.55, -0.45, -0.7}, 0.08, 0.25, mats.get("rocket", {2, 1}), seg, mats.get("coffee"));
    }
  } else if (family == "kitchen") {
    b.box({0, 0, -0.71}, {0.75, 0.75, 0.01}, 0, mats.get("gravel"), mats.get("text", {4, 8}, {0.6, 0.75, 0.95}));
    b.cylinder({-0.3, 0.25, -0.7}, 0.08, 0.3, mats.get("coffee", {2, 1}), seg, mats.get("clock"));
    b.cylinder({0.25, 0.3, -0.7}, 0.07, 0.22, mats.get("rocket", {2, 1}), seg, mats.get("gravel", {1, 1}, {0.9, 0.3, 0.3}));
    b.box({0.2, -0.25, -0.55}, {0.15, 0.06, 0.15}, 0.6, mats.get("chelsea"), mats.get("brick", {1, 1}, {0.95, 0.85, 0.4}));
    b.sphere({-0.25, -0.3, -0.6}, 0.1, mats.get("coffee"), seg);
    if (!tiny) {
      b.box({0.5, 0.0, -0.62}, {0.1, 0.2, 0.08}, -0.2, mats.get("astronaut"), mats.get("camera", {1, 1}, {0.5, 0.8, 0.6}));
      b.cylinder({0.0, 0.0, -0.7}, 0.12, 0.05, mats.get("brick", {3, 1}), seg, mats.get("hubble_deep_field"));
      b.sphere({-0.55, 0.0, -0.64}, 0.06, mats.get("chelsea"), seg);
    }
  } else {  // toys
    b.box({0, 0, -0.71}, {0.75, 0.75, 0.01}, 0, mats.get("grass"), mats.get("grass", {2, 2}, {0.45, 0.85, 0.35}));
    b.sphere({-0.25, 0.2, -0.55}, 0.15, mats.get("astronaut", {2, 1}), seg);
    b.sphere({0.3, -0.1, -0.6}, 0.1, mats.get("chelsea", {2, 1}), seg);
    b.box({0.1, 0.35, -0.6}, {0.1, 0.1, 0.1}, 0.3, mats.get("clock", {1, 1}, {0.4, 0.6, 1.0}), mats.get("camera", {1, 1}, {1.0, 0.85, 0.3}));
    b.cylinder({-0.2, -0.3, -0.7}, 0.05, 0.4, mats.get("rocket", {1, 1}), seg, mats.get("coffee"));
    if (!tiny) {
      b.box({0.35, 0.3, -0.65}, {0.05, 0.05, 0.05}, -0.5, mats.get("brick", {1, 1}, {1.0, 0.4, 0.4}));
      b.box({0.45, -0.45, -0.64}, {0.07, 0.07, 0.07}, 0.2, mats.get("hubble_deep_field"));
      b.sphere({-0.5, -0.5, -0.65}, 0.06, mats.get("coffee"), seg);
    }
  }
  p.scene.bvh = buildTriangleBvh(std::move(b.triangles));
}

// Many directional waves drawn from a spectrum: log-uniform wavelengths, directions spread
// around a random wind direction, amplitude ~ wavelength^1.5 (long waves carry the energy),
// scaled so that the surface's RMS slope is `rmsSlope`.
void setSpectrumWater(SynthPreset& p, SynthRng& rng, int count, double rmsSlope) {
  WaveSurface& w = p.water;
  w.meanHeight = 0;
  w.domain[0] = w.domain[1] = -1.5;
  w.domain[2] = w.domain[3] = 1.5;
  double wind = 360 * rng.uniform();
  double slope2 = 0;
  for (int i = 0; i < count; i++) {
    double wavelength = 0.12 * std::pow(0.7 / 0.12, rng.uniform());
    double direction = wind + 40 * rng.normal();
    double amplitude = std::pow(wavelength, 1.5) * (0.6 + 0.8 * rng.uniform());
    w.waves.push_back(sineAlong(amplitude, wavelength, direction, 2 * kPi * rng.uniform()));
    double ak = amplitude * 2 * kPi / wavelength;
    slope2 += 0.5 * ak * ak;
  }
  double scale = rmsSlope / std::sqrt(slope2);
  for (auto& wave : w.waves) wave.amplitude *= scale;
  p.surfaceDescription = std::to_string(count) + " directional sines from a spectrum (wavelengths 0.12-0.7 m log-uniform, directions "
                         "spread 40 deg around a random wind, amplitude ~ wavelength^1.5, RMS slope " +
                         std::to_string(rmsSlope).substr(0, 4) + ")";
}

}  // namespace

// Every object over the water must lie below the lowest trough (see render_view.cpp).
void checkSceneBelowWater(const SynthPreset& p) {
  const double* d = p.water.domain;
  double top = -1e300;
  for (const auto& t : p.scene.bvh.triangles) {
    glm::dvec3 lo = glm::min(glm::min(t.p[0], t.p[1]), t.p[2]), hi = glm::max(glm::max(t.p[0], t.p[1]), t.p[2]);
    if (hi.x <= d[0] || lo.x >= d[2] || hi.y <= d[1] || lo.y >= d[3]) continue;  // beside the water, not under it
    top = std::max(top, hi.z);
  }
  if (top >= p.water.meanHeight - waveHeightBound(p.water)) fail("synth preset " + p.name + ": the waves reach into the scene under the water");
}

int MaterialSet::get(const std::string& stem, glm::dvec2 uvScale, glm::dvec3 tint) {
  auto it = textureIndex.find(stem);
  if (it == textureIndex.end()) {
    it = textureIndex.emplace(stem, int(scene.textures.size())).first;
    scene.textures.push_back(loadSynthTexture(dir, stem));
  }
  scene.materials.push_back({it->second, uvScale, tint});
  return int(scene.materials.size()) - 1;
}

std::vector<std::string> synthPresetNames() {
  std::vector<std::string> names;
  for (const auto& e : presetTable()) names.push_back(e.name);
  return names;
}

bool isSynthPreset(const std::string& name) {
  for (const auto& e : presetTable())
    if (e.name == name) return true;
  return false;
}

SynthTexture loadSynthTexture(const std::string& textureDir, const std::string& stem) {
  std::string path = textureDir + "/" + stem + ".png";
  if (!fileExists(path)) fail("texture " + path + " not found (pass --textures DIR pointing at the repository's assets/textures)");
  Image img = readPng(path);
  SynthTexture t;
  t.name = stem;
  t.width = img.width;
  t.height = img.height;
  t.rgb.resize(size_t(img.width) * img.height * 3);
  for (int y = 0; y < img.height; y++)
    for (int x = 0; x < img.width; x++)
      for (int c = 0; c < 3; c++) t.rgb[(size_t(y) * img.width + x) * 3 + c] = img.at(x, y, img.channels >= 3 ? c : 0);
  return t;
}

SynthPreset makeSynthPreset(const std::string& name, SynthSize size, uint64_t seed, const std::string& textureDir) {
  const PresetEntry* entry = nullptr;
  for (const auto& e : presetTable())
    if (e.name == name) entry = &e;
  if (!entry) fail("unknown synth preset '" + name + "'");
  bool tiny = size == SynthSize::Tiny;
  SynthPreset p;
  p.name = name;
  p.samplesPerAxis = 2;
  p.heightMapSize = tiny ? 64 : 512;
  p.meshGridSize = tiny ? 33 : 257;
  MaterialSet mats{p.scene, textureDir, {}};
  SynthRng rng(mixKeys(seed, fnv1a(name)));
  if (entry->family == "nerfrac") {
    p.ior = 1.1;
    p.writeLlff = true;
    buildNerfracScene(p, mats, tiny);
    setNerfracWater(p, name, rng);
    int w = tiny ? 64 : 392;
    p.rigSpacing = 0.2;
    auto grid = gridCameras(0, 0, 1.0, p.rigSpacing, w, w, 45 * kDeg);
    for (int i = 0; i < 9; i++) (i == 4 ? p.test : p.train).push_back(grid[i]);
    p.air = p.test;  // the water-removal view is the held-out centre view
    p.between = betweenCameras(0, 0, 1.0, p.rigSpacing, w, w, 45 * kDeg);
    p.tiltableRig = true;
    p.rigPivot = {0, 0, -0.5};  // the top of the picture on the pool floor, 1.5 under the centre camera
    p.description = "NeRFrac-like synthetic scene: 3 x 3 downward cameras, centre held out, IOR 1.1, " + p.surfaceDescription;
  } else {
    p.ior = 1.33;
    buildRefracgsScene(p, mats, entry->family, tiny);
    setSpectrumWater(p, rng, tiny ? 6 : 24, 0.12);
    int w = tiny ? 64 : 400, h = w * 3 / 4;
    double fov = 50 * kDeg;
    glm::dvec3 centre(0, 0, -0.35);
    if (entry->topdown) {
      auto grid = gridCameras(0, 0, 1.3, 0.25, w, h, fov);
      for (int i = 0; i < 9; i++) (i == 4 ? p.test : p.train).push_back(grid[i]);
      p.air = p.test;
      p.between = betweenCameras(0, 0, 1.3, 0.25, w, h, fov);
      p.description = "RefracGS-like '" + entry->family + "' scene, 9 downward cameras (centre held out), IOR 1.33";
    } else {
      p.train = ringCameras(12, 30, 2.0, 0, centre, w, h, fov);
      auto outer = ringCameras(12, 45, 2.0, 15, centre, w, h, fov);
      p.train.insert(p.train.end(), outer.begin(), outer.end());
      p.test = ringCameras(6, 35, 2.0, 30, centre, w, h, fov);
      p.air = ringCameras(6, 30, 1.4, 0, centre, w, h, fov);
      p.description = "RefracGS-like '" + entry->family +
                      "' scene: 24 training views on rings at 30 and 45 deg, 6 test views at 35 deg, 6 water-removal views at 30 deg "
                      "nearer the centre, IOR 1.33";
    }
  }
  checkSceneBelowWater(p);
  return p;
}

namespace {

void applyCameraModel(SynthPreset& p, const std::string& model) {
  if (model == "pinhole") return;
  if (model != "opencv" && model != "fisheye") fail("synth: --camera-model must be pinhole, opencv or fisheye, got '" + model + "'");
  for (auto* cams : {&p.train, &p.test, &p.air, &p.between})
    for (auto& c : *cams) {
      c.lens = Lens{};
      if (model == "opencv") {
        c.lens.kind = LensKind::RadialTangential;
        c.lens.radial[0] = -0.25;
      } else {
        c.lens.kind = LensKind::Fisheye;
        c.cx = 0.5 * c.width, c.cy = 0.5 * c.height;
        c.fx = c.fy = std::hypot(c.cx, c.cy) / (0.5 * M_PI);  // theta = r / f: the corners 90 degrees off the axis
      }
    }
  p.writeLlff = false;
  p.description += model == "opencv" ? " (OpenCV lens, k1 = -0.25)" : " (equidistant fisheye, 180 degrees across the diagonal)";
}

}  // namespace

void applySynthVariation(SynthPreset& p, const SynthVariation& v) {
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (!positive(v.amplitudeScale)) fail("synth: the wave amplitude scale must be a positive number");
  if (!positive(v.wavelengthScale)) fail("synth: the wavelength scale must be a positive number");
  if (v.width != 0 && (v.width < 8 || v.width > 8192)) fail("synth: the image width must be in 8..8192");
  if (!std::isfinite(v.tiltDeg) || v.tiltDeg < 0 || v.tiltDeg > 60) fail("synth: the tilt must be 0..60 degrees from the vertical");
  if (v.tiltDeg != 0 && !p.tiltableRig) fail("synth: --tilt applies to the NeRFrac-like presets (their 3 x 3 downward rig) only");
  if (v.ior && !(std::isfinite(*v.ior) && *v.ior > 1 && *v.ior <= 2)) fail("synth: the IOR must be greater than 1 and at most 2");
  // Each view covers +-0.41 m of the water (45 deg from 1 m up): past 0.6 m apart the outer
  // views share almost nothing with the held-out centre view.
  if (v.rigSpacing && !(std::isfinite(*v.rigSpacing) && *v.rigSpacing > 0 && *v.rigSpacing <= 0.6))
    fail("synth: the rig spacing must be in (0, 0.6] m");
  if (v.rigSpacing && !p.tiltableRig) fail("synth: --rig-spacing applies to the NeRFrac-like presets (their 3 x 3 downward rig) only");
  for (auto& w : p.water.waves) {
    w.amplitude *= v.amplitudeScale;
    w.kx /= v.wavelengthScale;
    w.ky /= v.wavelengthScale;
  }
  for (auto& r : p.water.ripples) {
    r.amplitude *= v.amplitudeScale;
    r.k /= v.wavelengthScale;
  }
  if (v.amplitudeScale != 1 || v.wavelengthScale != 1) {
    char what[96];
    std::snprintf(what, sizeof what, " (amplitudes x%g, wavelengths x%g)", v.amplitudeScale, v.wavelengthScale);
    p.surfaceDescription += what;
    p.description += what;
  }
  if (v.ior) {
    char what[48];
    std::snprintf(what, sizeof what, " (IOR %g instead of %g)", *v.ior, p.ior);
    p.description += what;
    p.ior = *v.ior;
  }
  if (v.rigSpacing && *v.rigSpacing != p.rigSpacing) {
    // Every camera's offset from the rig's centre (the held-out centre view) scaled; the rig
    // is parallel, so heights and view axes stay.
    const glm::dvec3 centre = cameraCentre(p.test.front());
    const double scale = *v.rigSpacing / p.rigSpacing;
    for (auto* cams : {&p.train, &p.test, &p.air, &p.between})
      for (auto& c : *cams) {
        glm::dvec3 o = cameraCentre(c);
        c.cameraToWorld[3] = glm::dvec4(centre.x + scale * (o.x - centre.x), centre.y + scale * (o.y - centre.y), o.z, 1.0);
      }
    char what[64];
    std::snprintf(what, sizeof what, " (rig spacing %g m instead of %g)", *v.rigSpacing, p.rigSpacing);
    p.description += what;
    p.rigSpacing = *v.rigSpacing;
  }
  if (v.tiltDeg != 0) {
    for (auto* cams : {&p.train, &p.test, &p.air, &p.between})
      for (auto& c : *cams) {
        c = tiltedAboutX(c, p.rigPivot, v.tiltDeg);
        // A camera between the crests would see the water from below: not this scene.
        if (cameraCentre(c).z <= p.water.meanHeight + waveHeightBound(p.water)) {
          char why[96];
          std::snprintf(why, sizeof why, "synth: a tilt of %g degrees puts a camera under the wave crests", v.tiltDeg);
          fail(why);
        }
      }
    char what[96];
    std::snprintf(what, sizeof what, " (rig tilted %g deg from the vertical about the pool-floor centre)", v.tiltDeg);
    p.description += what;
  }
  if (v.width != 0)
    for (auto* cams : {&p.train, &p.test, &p.air, &p.between})
      for (auto& c : *cams) {
        double s = double(v.width) / c.width;
        c.height = std::max(1, int(std::lround(c.height * s)));
        c.width = v.width;
        c.fx *= s;
        c.fy *= s;
        c.cx *= s;
        c.cy *= s;
      }
  applyCameraModel(p, v.cameraModel);
  checkSceneBelowWater(p);
}

}  // namespace refrax::synth
