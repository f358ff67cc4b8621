#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Gaussian tracer backward with a compare-and-swap loop instead of float atomics (devices
// without shaderBufferFloat32AtomicAdd); see include/gaussian_backward_body.glsl.
#extension GL_GOOGLE_include_directive : require
#define REFRAX_CAS_ATOMICS
#include "gaussian_backward_body.glsl"
