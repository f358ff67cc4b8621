#version 460
#extension GL_GOOGLE_include_directive : require
// Weight-gradient pass with atomicAdd on floats (devices with shaderBufferFloat32AtomicAdd).
#extension GL_EXT_shader_atomic_float : require
#define REFRAX_FLOAT_ATOMIC_ADD
#include "height_weight_grad.glsl"
