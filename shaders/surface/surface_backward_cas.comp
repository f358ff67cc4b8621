#version 460
// Surface backward for devices without float atomics (compare-and-swap loop); body in
// include/surface_backward_body.glsl.
#extension GL_GOOGLE_include_directive : require
#include "surface_backward_body.glsl"
