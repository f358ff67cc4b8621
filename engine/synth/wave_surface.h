#pragma once
// The analytic water surface of the synthetic data generator: z = H(x, y), a mean height
// plus directional sine waves and radially symmetric ripples, over a rectangular domain.
// Closed-form height and gradient give the ground truth that trained surfaces are scored on.
#include <glm/glm.hpp>
#include <vector>

namespace refrax::synth {

// amplitude * sin(kx * x + ky * y + phase)
struct DirectionalWave {
  double amplitude, kx, ky, phase;
};

// amplitude * cos(k * r) * exp(-r^2 / (2 sigma^2)), r = distance to (cx, cy). Cosine (not a
// phase-shifted sine) keeps the surface smooth at the centre.
struct RadialRipple {
  double amplitude, cx, cy, k, sigma;
};

struct WaveSurface {
  double meanHeight = 0;
  double domain[4] = {-1, -1, 1, 1};  // xmin, ymin, xmax, ymax
  std::vector<DirectionalWave> waves;
  std::vector<RadialRipple> ripples;
};

double waveHeight(const WaveSurface& s, double x, double y);
glm::dvec2 waveGradient(const WaveSurface& s, double x, double y);
// Upward unit normal (-Hx, -Hy, 1) / |.|.
glm::dvec3 waveNormal(const WaveSurface& s, double x, double y);
// Bound on |H - meanHeight| (sum of amplitudes).
double waveHeightBound(const WaveSurface& s);
// Lipschitz bound on |grad H| over the whole plane.
double waveSlopeBound(const WaveSurface& s);

}  // namespace refrax::synth
