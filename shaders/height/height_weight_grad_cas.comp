#version 460
#extension GL_GOOGLE_include_directive : require
// Weight-gradient pass with a compare-and-swap float add (devices without float atomics).
#include "height_weight_grad.glsl"
