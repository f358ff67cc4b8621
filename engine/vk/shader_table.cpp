#include "engine/vk/shader_table.h"

#include <cstring>
#include <string>

#include "engine/base/error.h"

namespace refrax {

const EmbeddedShader& findShader(const char* name) {
  size_t count = 0;
  const EmbeddedShader* all = embeddedShaders(&count);
  for (size_t i = 0; i < count; i++)
    if (std::strcmp(all[i].name, name) == 0) return all[i];
  fail(std::string("no embedded shader named '") + name + "'");
}

}  // namespace refrax
