#pragma once
// The SPIR-V of every shaders/<stage>/*.comp, embedded at build time (cmake/EmbedShaders.cmake).
#include <cstddef>
#include <cstdint>

namespace refrax {

struct EmbeddedShader {
  const char* name;      // file name without ".comp"
  const uint32_t* code;  // SPIR-V words
  size_t bytes;
};

const EmbeddedShader* embeddedShaders(size_t* count);
// The shader called `name`; throws refrax::Error when the build has no such shader.
const EmbeddedShader& findShader(const char* name);

}  // namespace refrax
