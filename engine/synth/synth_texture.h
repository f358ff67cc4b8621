#pragma once
// RGB textures for the synthetic scenes, sampled bilinearly with repeat wrapping.
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace refrax::synth {

struct SynthTexture {
  std::string name;
  int width = 0, height = 0;
  std::vector<float> rgb;  // row 0 is the top of the image, values in [0, 1]
};

// u to the right, v up (v = 0 is the bottom row); texel centres at (i + 0.5) / width.
glm::dvec3 sampleBilinear(const SynthTexture& tex, double u, double v);

}  // namespace refrax::synth
