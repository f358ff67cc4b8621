#version 460
// Gaussian tracer backward with a compare-and-swap loop instead of float atomics (devices
// without shaderBufferFloat32AtomicAdd); see include/gaussian_backward_body.glsl.
#extension GL_GOOGLE_include_directive : require
#define REFRAX_CAS_ATOMICS
#include "gaussian_backward_body.glsl"
