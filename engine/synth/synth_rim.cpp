#include "engine/synth/synth_rim.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/base/error.h"

namespace refrax::synth {

void addSynthRim(SynthPreset& p, double a, const std::string& textureDir) {
  WaveSurface& w = p.water;
  const double cx = 0.5 * (w.domain[0] + w.domain[2]), cy = 0.5 * (w.domain[1] + w.domain[3]);
  const double maxOpening = 0.5 * std::min(w.domain[2] - w.domain[0], w.domain[3] - w.domain[1]);
  if (!(std::isfinite(a) && a > 0 && a <= maxOpening)) {
    char why[160];
    std::snprintf(why, sizeof why, "synth: --rim must be a half-width in (0, %g] m (the preset's water domain)", maxOpening);
    fail(why);
  }
  const double top = w.meanHeight + waveHeightBound(w) + kRimFreeboard;
  for (const auto* cams : {&p.train, &p.test, &p.air, &p.between})
    for (const auto& c : *cams) {
      glm::dvec3 o = cameraCentre(c);
      if (std::abs(o.x - cx) <= 2 * a && std::abs(o.y - cy) <= 2 * a && o.z <= top) fail("synth: --rim would put a camera inside the rim or under its top");
    }

  double bottom = top - 0.1;
  for (const auto& t : p.scene.bvh.triangles)
    for (const auto& v : t.p) bottom = std::min(bottom, v.z);

  // Each block its own photograph, so that no two parts of the rim look alike to a feature
  // matcher (a tiled texture would give repeated, ambiguous features).
  MaterialSet materials{p.scene, textureDir, {}};
  const int wall = materials.get("brick", {3, 1}, {0.8, 0.75, 0.7});
  struct Block {
    double x, y;  // centre, in units of the half-opening
    const char* texture;
  };
  // Four sides (2a x a) and four corners (a x a) tile the frame from +-a out to +-2a.
  const Block blocks[] = {{0, 1.5, "astronaut"},  {0, -1.5, "chelsea"},     {1.5, 0, "coffee"},     {-1.5, 0, "camera"},
                          {1.5, 1.5, "clock"},    {-1.5, 1.5, "rocket"},    {1.5, -1.5, "hubble_deep_field"}, {-1.5, -1.5, "text"}};
  SceneBuilder b{std::move(p.scene.bvh.triangles)};
  const double hz = 0.5 * (top - bottom), zc = 0.5 * (top + bottom);
  for (const Block& k : blocks) {
    glm::dvec3 half(k.x == 0 ? a : 0.5 * a, k.y == 0 ? a : 0.5 * a, hz);
    b.box({cx + k.x * a, cy + k.y * a, zc}, half, 0, wall, materials.get(k.texture));
  }
  p.scene.bvh = buildTriangleBvh(std::move(b.triangles));
  p.scene.geometryAboveWater = true;

  w.domain[0] = cx - a;
  w.domain[1] = cy - a;
  w.domain[2] = cx + a;
  w.domain[3] = cy + a;
  char what[160];
  std::snprintf(what, sizeof what, " (dry textured rim: water in +-%g m, rim out to +-%g m, its top %g m above the mean water)", a, 2 * a,
                top - w.meanHeight);
  p.description += what;
  checkSceneBelowWater(p);
}

}  // namespace refrax::synth
