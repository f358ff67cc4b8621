#pragma once
// The C++ side of the GLSL/C++ shared math (see shaders/include/shared_prelude.glsl):
// two namespaces with the GLSL vocabulary, f32 matching the shaders and f64 the reference.
// A wrapper header includes a shared .glsl header inside each of them, e.g.
//   #include "engine/base/shared_math.h"
//   namespace refrax::f32 {
//   #include "snell.glsl"
//   }
//   namespace refrax::f64 {
//   #include "snell.glsl"
//   }
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

#include "shared_prelude.glsl"

#define REFRAX_SHARED_VOCABULARY(T, P)                                                              \
  using real = T;                                                                                   \
  using real2 = glm::vec<2, T, glm::defaultp>;                                                      \
  using real3 = glm::vec<3, T, glm::defaultp>;                                                      \
  using real4 = glm::vec<4, T, glm::defaultp>;                                                      \
  using real3x3 = glm::mat<3, 3, T, glm::defaultp>;                                                 \
  using uint = uint32_t;                                                                            \
  using glm::abs, glm::clamp, glm::cross, glm::dot, glm::length, glm::max, glm::min, glm::mix,      \
      glm::normalize, glm::sign, glm::floor, glm::fract, glm::transpose, glm::inverse;              \
  using std::sqrt, std::exp, std::log, std::sin, std::cos, std::pow, std::isnan, std::isinf, std::atan;                   \
  inline T atan(T y, T x) { return std::atan2(y, x); } /* GLSL's two-argument atan */

namespace refrax::f32 {
REFRAX_SHARED_VOCABULARY(float, f)
}
namespace refrax::f64 {
REFRAX_SHARED_VOCABULARY(double, d)
}
