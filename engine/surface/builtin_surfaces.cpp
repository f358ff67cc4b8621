#include "engine/surface/builtin_surfaces.h"

#include <cmath>

#include "engine/base/error.h"

namespace refrax {

std::function<float(float, float)> surfaceHeightFunction(const BuiltinSurface& s) {
  if (s.kind == "flat") return [h = s.height](float, float) { return h; };
  if (!(s.wavelength > 0.0f)) fail("surface wavelength must be positive");
  const float k = 2.0f * float(M_PI) / s.wavelength;
  const float cx = std::cos(s.directionDeg * float(M_PI) / 180.0f), cy = std::sin(s.directionDeg * float(M_PI) / 180.0f);
  if (s.kind == "sine")
    return [=](float x, float y) { return s.height + s.amplitude * std::sin(k * (cx * x + cy * y)); };
  if (s.kind == "triangle")
    return [=](float x, float y) {
      float phase = (cx * x + cy * y) / s.wavelength;
      float f = phase - std::floor(phase);                      // 0..1
      return s.height + s.amplitude * (4.0f * std::fabs(f - 0.5f) - 1.0f);  // -1..1 triangle
    };
  fail("unknown surface '" + s.kind + "' (flat, sine or triangle)");
}

}  // namespace refrax
