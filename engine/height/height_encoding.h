#pragma once
// C++ side of shaders/include/height_encoding.glsl: f32 matches the shaders, f64 is the reference.
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "height_encoding.glsl"
}
namespace refrax::f64 {
#include "height_encoding.glsl"
}
