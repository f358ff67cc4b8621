// The weight-gradient output of the backward kernels (binding 1) and the one way they add
// to it: atomicAdd on floats where the device has it (REFRAX_FLOAT_ATOMIC_ADD, with
// GL_EXT_shader_atomic_float enabled by the including shader), else a compare-and-swap loop.
#ifndef REFRAX_HEIGHT_GRAD_OUTPUT_GLSL
#define REFRAX_HEIGHT_GRAD_OUTPUT_GLSL
#ifdef REFRAX_FLOAT_ATOMIC_ADD
layout(std430, set = 0, binding = 1) buffer Grad { float grad[]; };
void addToGradient(uint index, float v) { atomicAdd(grad[index], v); }
#else
layout(std430, set = 0, binding = 1) buffer Grad { uint gradBits[]; };
void addToGradient(uint index, float v) {
  uint expected = gradBits[index];
  for (;;) {
    uint seen = atomicCompSwap(gradBits[index], expected, floatBitsToUint(uintBitsToFloat(expected) + v));
    if (seen == expected) break;
    expected = seen;
  }
}
#endif
#endif
