#include "engine/synth/surface_intersect.h"

#include <algorithm>
#include <cmath>

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

  auto f = [&](double t) { return o.z + t * d.z - waveHeight(s, o.x + t * d.x, o.y + t * d.y); };
  // |f'(t)| = |d.z - grad H . d.xy| <= |d.z| + slope * |d.xy|.
  double lipschitz = std::abs(d.z) + waveSlopeBound(s) * std::hypot(d.x, d.y);
  double stepFloor = minStep / len;

  double ta = t0, fa = f(ta);
  if (fa == 0) return SurfaceCrossing{ta, d.z - glm::dot(waveGradient(s, o.x + ta * d.x, o.y + ta * d.y), glm::dvec2(d.x, d.y)) < 0};
  while (ta < t1) {
    double tb = std::min(t1, ta + std::max(std::abs(fa) / lipschitz, stepFloor));
    double fb = f(tb);
    if ((fa > 0) != (fb > 0)) {
      bool downward = fa > 0;
      // Bisection keeps the bracket [ta, tb] with f(ta), f(tb) of opposite signs.
      for (int i = 0; i < 200 && tb - ta > 1e-13 * std::max(1.0, std::abs(tb)); i++) {
        double tm = 0.5 * (ta + tb), fm = f(tm);
        if ((fm > 0) == (fa > 0)) {
          ta = tm;
          fa = fm;
        } else {
          tb = tm;
        }
      }
      return SurfaceCrossing{0.5 * (ta + tb), downward};
    }
    ta = tb;
    fa = fb;
  }
  return std::nullopt;
}

}  // namespace refrax::synth
