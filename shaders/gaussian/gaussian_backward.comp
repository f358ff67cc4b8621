#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Gaussian tracer backward with float atomicAdd (VK_EXT_shader_atomic_float); see
// include/gaussian_backward_body.glsl.
#extension GL_GOOGLE_include_directive : require
#include "gaussian_backward_body.glsl"
