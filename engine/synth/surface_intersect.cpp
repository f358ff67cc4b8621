#include "engine/synth/surface_intersect.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace refrax::synth {

namespace {
// Clips [t0, t1] to the slab lo <= o + t d <= hi along one axis; false when empty.
bool clipSlab(double o, double d, double lo, double hi, double& t0, double& t1) {
  if (d == 0) return o >= lo && o <= hi;
  double a = (lo - o) / d, b = (hi - o) / d;
  if (a > b) std::swap(a, b);
  t0 = std::max(t0, a);
  t1 = std::min(t1, b);
  return t0 <= t1;
}

// f(t) = z(t) - H(x(t), y(t)) along one ray. A directional wave's phase is linear in t, so
// it is precomputed per ray (phase0 + t * rate); ripples are evaluated directly.
struct RayHeightGap {
  const WaveSurface& s;
  glm::dvec3 o, d;
  // Per-ray coefficients on the stack for the common case (no allocation per ray).
  static constexpr size_t kInline = 64;
  double inlineStore[3 * kInline];
  std::vector<double> heapStore;
  double *amplitude, *phase0, *rate;
  size_t count;

  RayHeightGap(const WaveSurface& surface, const glm::dvec3& origin, const glm::dvec3& dir) : s(surface), o(origin), d(dir) {
    count = s.waves.size();
    double* store = inlineStore;
    if (count > kInline) {
      heapStore.resize(3 * count);
      store = heapStore.data();
    }
    amplitude = store;
    phase0 = store + count;
    rate = store + 2 * count;
    for (size_t i = 0; i < count; i++) {
      const auto& w = s.waves[i];
      amplitude[i] = w.amplitude;
      phase0[i] = w.kx * o.x + w.ky * o.y + w.phase;
      rate[i] = w.kx * d.x + w.ky * d.y;
    }
  }
  RayHeightGap(const RayHeightGap&) = delete;
  double operator()(double t) const {
    double h = s.meanHeight;
    for (size_t i = 0; i < count; i++) h += amplitude[i] * std::sin(phase0[i] + t * rate[i]);
    double x = o.x + t * d.x, y = o.y + t * d.y;
    for (const auto& r : s.ripples) {
      double dx = x - r.cx, dy = y - r.cy, r2 = dx * dx + dy * dy;
      h += r.amplitude * std::cos(r.k * std::sqrt(r2)) * std::exp(-r2 / (2 * r.sigma * r.sigma));
    }
    return o.z + t * d.z - h;
  }
  // Bound on |f'(t)|: |d.z| plus the bound on the directional derivative of H along d.xy.
  double lipschitz() const {
    double b = std::abs(d.z);
    for (size_t i = 0; i < count; i++) b += std::abs(amplitude[i] * rate[i]);
    for (const auto& r : s.ripples) b += std::abs(r.amplitude) * (std::abs(r.k) + 1.0 / (r.sigma * std::sqrt(std::exp(1.0)))) * std::hypot(d.x, d.y);
    return b;
  }
};
}  // namespace

std::optional<SurfaceCrossing> intersectWaveSurface(const WaveSurface& s, const glm::dvec3& o, const glm::dvec3& d, double tMax,
                                                     double minStep) {
  double len = glm::length(d);
  if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
  // The surface lives in the box domain x [mean - bound, mean + bound].
  double bound = waveHeightBound(s) * (1 + 1e-12) + 1e-12;
  double t0 = 0, t1 = tMax;
  if (!clipSlab(o.x, d.x, s.domain[0], s.domain[2], t0, t1) || !clipSlab(o.y, d.y, s.domain[1], s.domain[3], t0, t1) ||
      !clipSlab(o.z, d.z, s.meanHeight - bound, s.meanHeight + bound, t0, t1))
    return std::nullopt;

  RayHeightGap f(s, o, d);
  double lipschitz = f.lipschitz();
  if (!(lipschitz > 0)) return std::nullopt;
  double stepFloor = minStep / len;

  double ta = t0, fa = f(ta);
  if (fa == 0) {
    glm::dvec2 g = waveGradient(s, o.x + ta * d.x, o.y + ta * d.y);
    return SurfaceCrossing{ta, d.z - glm::dot(g, glm::dvec2(d.x, d.y)) < 0};
  }
  while (ta < t1) {
    // |f| / L is the shortest distance at which f can reach zero: no root is skipped.
    double tb = std::min(t1, ta + std::max(std::abs(fa) / lipschitz, stepFloor));
    double fb = f(tb);
    if ((fa > 0) != (fb > 0)) {
      bool downward = fa > 0;
      // Illinois (modified regula falsi) keeps the bracket and converges superlinearly.
      int side = 0;
      for (int i = 0; i < 100 && tb - ta > 1e-12 * std::max(1.0, std::abs(tb)); i++) {
        double tm = (ta * fb - tb * fa) / (fb - fa);
        if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
        double fm = f(tm);
        if (fm == 0) return SurfaceCrossing{tm, downward};
        if ((fm > 0) == (fa > 0)) {
          ta = tm;
          fa = fm;
          if (side == -1) fb *= 0.5;
          side = -1;
        } else {
          tb = tm;
          fb = fm;
          if (side == 1) fa *= 0.5;
          side = 1;
        }
        if (std::abs(fm) < 1e-15) return SurfaceCrossing{tm, downward};
      }
      return SurfaceCrossing{0.5 * (ta + tb), downward};
    }
    ta = tb;
    fa = fb;
  }
  return std::nullopt;
}

}  // namespace refrax::synth
