#pragma once
// Exact first intersection of a ray with the analytic wave surface, independent of the
// trainer's proxy-mesh tracer: Lipschitz-bounded marching brackets the first sign change of
// f(t) = z(t) - H(x(t), y(t)), then Illinois regula falsi pins it to ~1e-13 relative.
#include <glm/glm.hpp>
#include <optional>

#include "engine/synth/wave_surface.h"

namespace refrax::synth {

struct SurfaceCrossing {
  double t;
  bool downward;  // the ray passes from above the surface to below it
};

// First crossing of o + t d (t in [0, tMax]) with z = H(x, y) inside the surface domain.
// Marching steps by |f| / M (M bounds |f'|), so it cannot step over a root, but never by less
// than minStep (in units of length along the ray, default 10 micrometres): two roots closer together
// than that (a ray grazing a crest) may be reported as none.
std::optional<SurfaceCrossing> intersectWaveSurface(const WaveSurface& s, const glm::dvec3& o, const glm::dvec3& d,
                                                     double tMax = 1e30, double minStep = 1e-5);

}  // namespace refrax::synth
