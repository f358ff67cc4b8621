// Prelude of every header whose math is shared by GLSL shaders and the C++ reference
// ("one place for each piece of math"). A shared header is written once in the common
// subset of GLSL and GLM C++:
//   - types `real`, `real2`, `real3`, `real4`, `real3x3`, `uint`; literals as real(0.5)
//   - functions from GLSL/GLM only: dot cross normalize length min max clamp sqrt exp
//     abs mix floor fract sin cos ... (the C++ wrappers bring them in with `using`)
//   - out/inout parameters as OUT(real3) x / INOUT(real) y; functions marked SHARED_FN
//   - no include guard in C++: engine/base/shared_math.h includes such a header twice, inside
//     refrax::f32 (real = float, the shaders' precision) and refrax::f64 (the double
//     reference); in GLSL guard with #ifndef as usual.
// In GLSL, `real` is float. Shaders include the header directly.
#ifdef __cplusplus
#define OUT(T) T&
#define INOUT(T) T&
#define SHARED_FN inline
#else
#ifndef REFRAX_SHARED_PRELUDE
#define REFRAX_SHARED_PRELUDE
#define OUT(T) out T
#define INOUT(T) inout T
#define SHARED_FN
#define real float
#define real2 vec2
#define real3 vec3
#define real4 vec4
#define real3x3 mat3
#endif
#endif
