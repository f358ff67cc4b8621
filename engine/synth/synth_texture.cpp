#include "engine/synth/synth_texture.h"

#include <cmath>

namespace refrax::synth {

namespace {
int wrap(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}
}  // namespace

glm::dvec3 sampleBilinear(const SynthTexture& tex, double u, double v) {
  double x = u * tex.width - 0.5, y = (1.0 - v) * tex.height - 0.5;
  double fx = std::floor(x), fy = std::floor(y);
  double ax = x - fx, ay = y - fy;
  int x0 = wrap(int(fx), tex.width), x1 = wrap(int(fx) + 1, tex.width);
  int y0 = wrap(int(fy), tex.height), y1 = wrap(int(fy) + 1, tex.height);
  auto texel = [&](int xi, int yi) {
    const float* p = &tex.rgb[(size_t(yi) * tex.width + xi) * 3];
    return glm::dvec3(p[0], p[1], p[2]);
  };
  return (texel(x0, y0) * (1 - ax) + texel(x1, y0) * ax) * (1 - ay) + (texel(x0, y1) * (1 - ax) + texel(x1, y1) * ax) * ay;
}

}  // namespace refrax::synth
