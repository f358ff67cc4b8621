#include "engine/synth/bottom_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/synth/render_view.h"
#include "engine/synth/wave_surface.h"

namespace refrax::synth {

BottomTruth renderBottomTruth(const SynthPreset& p) {
  const WaveSurface& w = p.water;
  BottomTruth t;
  t.size = p.heightMapSize;
  const size_t n = size_t(t.size);
  t.elevation.assign(n * n, std::numeric_limits<float>::quiet_NaN());
  t.rgb.assign(n * n * 3, 0.0f);
  // Every triangle over the domain lies under the lowest trough (checkSceneBelowWater), so a
  // ray starting above the highest crest starts above all of it.
  const double top = w.meanHeight + waveHeightBound(w) + 1.0;
  const glm::dvec3 down(0, 0, -1);
  for (size_t j = 0; j < n; j++)
    for (size_t i = 0; i < n; i++) {
      const double x = w.domain[0] + (w.domain[2] - w.domain[0]) * double(i) / double(n - 1);
      const double y = w.domain[1] + (w.domain[3] - w.domain[1]) * double(j) / double(n - 1);
      const RayResult r = shadeCameraRay(p.scene, nullptr, p.ior, {x, y, top}, down);
      const size_t k = j * n + i;
      if (r.hitScene) t.elevation[k] = float(r.scenePoint.z);
      for (int c = 0; c < 3; c++) t.rgb[3 * k + c] = float(std::clamp(r.colour[c], 0.0, 1.0));
    }
  return t;
}

}  // namespace refrax::synth
