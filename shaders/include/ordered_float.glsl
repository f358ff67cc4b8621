// Floats as unsigned integers that order as the floats do (negative below positive), so a
// float min/max can be taken with integer atomics (atomicMin/atomicMax on uint).
#ifndef REFRAX_ORDERED_FLOAT_GLSL
#define REFRAX_ORDERED_FLOAT_GLSL
uint floatToOrdered(float f) {
  uint u = floatBitsToUint(f);
  return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}
float orderedToFloat(uint o) { return uintBitsToFloat((o & 0x80000000u) != 0u ? (o & 0x7FFFFFFFu) : ~o); }
#endif
