#pragma once
// The analytic test height H(x, y) shared with the shaders (shaders/include/analytic_height.glsl),
// compiled as C++ in refrax::f32 (the shaders' precision) and refrax::f64 (the double
// reference). The surface's math (engine/surface/surface_math.h) builds on it.
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "analytic_height.glsl"
}  // namespace refrax::f32

namespace refrax::f64 {
#include "analytic_height.glsl"
}  // namespace refrax::f64
