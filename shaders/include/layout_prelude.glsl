// Prelude of the std430 records that the shaders and the host share, each declared once (as
// shared_prelude.glsl does for the math): a record's .glsl header is included by the shaders
// and, through engine/base/gpu_layout.h, by the C++ host inside namespace refrax.
//   LAYOUT_STRUCT(GlslName, HostName)   opens the record (GLSL and C++ may name it apart)
//     LAYOUT_UINT(name), LAYOUT_FLOAT(name)  a 4-byte scalar
//     LAYOUT_VEC4(name)                 GLSL vec4, host float[4]
//     LAYOUT_XYZ_W(xyz, w, glslName)    GLSL vec4 glslName; host float xyz[3] and float w
//     LAYOUT_VEC3(name)                 GLSL vec3, host float[3]: a 4-byte scalar must follow
//                                       (std430 aligns a vec3 to 16 bytes, C++ to 4)
//   LAYOUT_END(HostName, bytes)         closes it; the host checks its size is `bytes`
//   LAYOUT_CONST(name, value)           a uint constant on both sides
//   LAYOUT_FN                           marks a function written in the common subset
// Only these fields exist, each 4-byte aligned and a vec3 always followed by a scalar, so the
// std430 offsets are the C++ ones; the size check catches a field added on one side only
// (there is no other side to add it to).
#ifndef REFRAX_LAYOUT_PRELUDE
#define REFRAX_LAYOUT_PRELUDE
#ifdef __cplusplus
#define LAYOUT_STRUCT(glslName, hostName) struct hostName {
#define LAYOUT_END(hostName, bytes) \
  };                                \
  static_assert(sizeof(hostName) == bytes, #hostName " must hold its std430 size");
#define LAYOUT_UINT(name) uint32_t name;
#define LAYOUT_FLOAT(name) float name;
#define LAYOUT_VEC4(name) float name[4];
#define LAYOUT_XYZ_W(xyz, w, glslName) float xyz[3]; float w;
#define LAYOUT_VEC3(name) float name[3];
#define LAYOUT_CONST(name, value) constexpr uint32_t name = value;
#define LAYOUT_FN inline
#else
#define LAYOUT_STRUCT(glslName, hostName) struct glslName {
#define LAYOUT_END(hostName, bytes) };
#define LAYOUT_UINT(name) uint name;
#define LAYOUT_FLOAT(name) float name;
#define LAYOUT_VEC4(name) vec4 name;
#define LAYOUT_XYZ_W(xyz, w, glslName) vec4 glslName;
#define LAYOUT_VEC3(name) vec3 name;
#define LAYOUT_CONST(name, value) const uint name = value;
#define LAYOUT_FN
#endif
#endif
