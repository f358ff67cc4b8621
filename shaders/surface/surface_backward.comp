#version 460
// Surface backward with float atomics (VK_EXT_shader_atomic_float); body in
// include/surface_backward_body.glsl.
#extension GL_EXT_shader_atomic_float : require
#extension GL_GOOGLE_include_directive : require
#define REFRAX_FLOAT_ATOMICS
#include "surface_backward_body.glsl"
