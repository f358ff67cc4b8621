#pragma once
// The surface math shared with the shaders (Snell, lattice, intersection, normals and their
// backward; the analytic test surface; refraction on a swapped-in mesh), compiled as C++ in
// refrax::f32 (the shaders' precision) and refrax::f64 (the double reference). See shaders/include/*.glsl.
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "analytic_height.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "mesh_refract.glsl"
}  // namespace refrax::f32

namespace refrax::f64 {
#include "analytic_height.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "mesh_refract.glsl"
}  // namespace refrax::f64
