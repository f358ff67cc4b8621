#pragma once
// A dry, textured rim around the water (a pool's edge) for `refrax synth --rim`: the water's
// domain shrinks to a square opening and a frame of photo-textured blocks surrounds it, its
// top just above the highest crest, its walls down to the pool floor. Views that see only
// water cannot be registered by structure from motion (what the water shows changes from view
// to view); the rim is the part of every view that stays put, so COLMAP can pose the cameras.
#include <string>

#include "engine/synth/synth_presets.h"

namespace refrax::synth {

// Opening (the new water domain): +-halfOpening around the old domain's centre; the rim
// reaches out to +-2 halfOpening. refrax::Error when the opening is not a positive number at
// most the old domain's smaller half-width, or when a camera would sit inside the rim (at or
// below its top over its footprint). Applied after applySynthVariation: it checks the cameras
// where they end up.
void addSynthRim(SynthPreset& preset, double halfOpening, const std::string& textureDir);

// The rim's top: this far above the highest crest (metres), so no wave reaches over it.
constexpr double kRimFreeboard = 0.02;

}  // namespace refrax::synth
