#pragma once
// Built-in water surfaces for swapping in place of the learned one (viewer, `refrax render
// --surface`): flat, a sine wave and a triangular wave, as height functions z = f(x, y).
#include <functional>
#include <string>

namespace refrax {

struct BuiltinSurface {
  std::string kind = "flat";  // flat | sine | triangle
  float height = 0.0f;        // mean water level
  float amplitude = 0.02f;
  float wavelength = 0.5f;
  float directionDeg = 0.0f;  // wave travel direction in the xy plane
};

// The height function; refrax::Error for an unknown kind or a non-positive wavelength.
std::function<float(float, float)> surfaceHeightFunction(const BuiltinSurface& s);

}  // namespace refrax
