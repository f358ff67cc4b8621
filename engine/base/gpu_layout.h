#pragma once
// The C++ side of the std430 records shared with the shaders (shaders/include/layout_prelude.glsl):
// a host header includes a record's .glsl inside namespace refrax, e.g.
//   #include "engine/base/gpu_layout.h"
//   namespace refrax {
//   #include "rays.glsl"
//   }
#include <cstdint>

#include "layout_prelude.glsl"

namespace refrax {
using uint = uint32_t;  // the GLSL name, for functions a record's header shares (LAYOUT_FN)
}
