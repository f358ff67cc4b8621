#pragma once
// C++ side of shaders/include/densify_split.glsl: a split child's offset from counter-based
// normals, in float (refrax::f32, as the device's densify draws it) and double (refrax::f64,
// the host's densify).
#include "engine/gaussian/gaussian_math.h"

namespace refrax::f32 {
#include "densify_split.glsl"
}
namespace refrax::f64 {
#include "densify_split.glsl"
}
