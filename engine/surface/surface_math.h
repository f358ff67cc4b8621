#pragma once
// The surface math shared with the shaders (Snell, lattice, intersection, normals and their
// backward; refraction on a swapped-in mesh; the analytic test surface from engine/height/height_math.h), compiled as C++ in
// refrax::f32 (the shaders' precision) and refrax::f64 (the double reference). See shaders/include/*.glsl.
#include "engine/base/shared_math.h"
#include "engine/height/height_math.h"  // the analytic test surface, in both namespaces

namespace refrax::f32 {
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "mesh_refract.glsl"
}  // namespace refrax::f32

namespace refrax::f64 {
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "mesh_refract.glsl"
}  // namespace refrax::f64
