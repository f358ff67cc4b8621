#pragma once
// The shared lens and camera-direction math (shaders/include/camera_direction.glsl, lens.glsl)
// in C++: f32 as the shaders compute it, f64 the double reference.
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "camera_direction.glsl"
}
namespace refrax::f64 {
#include "camera_direction.glsl"
}
