#include "engine/synth/wave_surface.h"

#include <cmath>

namespace refrax::synth {

double waveHeight(const WaveSurface& s, double x, double y) {
  double h = s.meanHeight;
  for (const auto& w : s.waves) h += w.amplitude * std::sin(w.kx * x + w.ky * y + w.phase);
  for (const auto& r : s.ripples) {
    double dx = x - r.cx, dy = y - r.cy, r2 = dx * dx + dy * dy;
    h += r.amplitude * std::cos(r.k * std::sqrt(r2)) * std::exp(-r2 / (2 * r.sigma * r.sigma));
  }
  return h;
}

glm::dvec2 waveGradient(const WaveSurface& s, double x, double y) {
  glm::dvec2 g(0.0);
  for (const auto& w : s.waves) {
    double c = w.amplitude * std::cos(w.kx * x + w.ky * y + w.phase);
    g += glm::dvec2(c * w.kx, c * w.ky);
  }
  for (const auto& r : s.ripples) {
    double dx = x - r.cx, dy = y - r.cy, r2 = dx * dx + dy * dy, rr = std::sqrt(r2);
    double envelope = std::exp(-r2 / (2 * r.sigma * r.sigma));
    // (dH/dr) / r, written so that r = 0 needs no special direction: sin(kr)/r -> k.
    double sincTerm = r.k * rr < 1e-8 ? r.k : std::sin(r.k * rr) / rr;
    double dHdrOverR = r.amplitude * envelope * (-r.k * sincTerm - std::cos(r.k * rr) / (r.sigma * r.sigma));
    g += glm::dvec2(dHdrOverR * dx, dHdrOverR * dy);
  }
  return g;
}

glm::dvec3 waveNormal(const WaveSurface& s, double x, double y) {
  glm::dvec2 g = waveGradient(s, x, y);
  return glm::normalize(glm::dvec3(-g.x, -g.y, 1.0));
}

double waveHeightBound(const WaveSurface& s) {
  double b = 0;
  for (const auto& w : s.waves) b += std::abs(w.amplitude);
  for (const auto& r : s.ripples) b += std::abs(r.amplitude);
  return b;
}

double waveSlopeBound(const WaveSurface& s) {
  double b = 0;
  for (const auto& w : s.waves) b += std::abs(w.amplitude) * std::hypot(w.kx, w.ky);
  // |d/dr (cos(kr) e(r))| <= k + max_r (r / sigma^2) e(r) = k + 1 / (sigma sqrt(e)).
  for (const auto& r : s.ripples) b += std::abs(r.amplitude) * (std::abs(r.k) + 1.0 / (r.sigma * std::sqrt(std::exp(1.0))));
  return b;
}

}  // namespace refrax::synth
