#pragma once
// C++ side of shaders/include/gaussian_math.glsl: the Gaussian kernel, hit rules, SH and
// their derivatives, in float (refrax::f32, as the shaders compute) and double (refrax::f64,
// the reference).
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "gaussian_math.glsl"
}
namespace refrax::f64 {
#include "gaussian_math.glsl"
}
