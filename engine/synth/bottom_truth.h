#pragma once
// What lies under the water, as a surveyor maps it (issue 49's truth): on the water's height
// map grid over its domain, the elevation of the first scene surface a vertical ray meets with
// the water removed (the bed, or an object on it), and that surface's colour seen straight
// down (a true orthophoto: every point from directly above, no perspective, no refraction).
#include <vector>

#include "engine/synth/synth_presets.h"

namespace refrax::synth {

struct BottomTruth {
  int size = 0;                  // grid vertices per side: the height map's (SynthPreset::heightMapSize)
  std::vector<float> elevation;  // [j][i]: z at x = xmin + i (xmax - xmin) / (size - 1), y likewise; NaN where the ray met nothing
  std::vector<float> rgb;        // the same grid, 3 per vertex, in [0, 1]; the scene's background where the ray met nothing
};

BottomTruth renderBottomTruth(const SynthPreset& preset);

}  // namespace refrax::synth
