// glTF water meshes, as .gltf (JSON) or .glb (binary) by the input's first byte.
#include "engine/surface/gltf_surface.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  const bool binary = size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F';
  const std::string path = fuzz::writeInput(binary ? "water.glb" : "water.gltf", data, size);
  return fuzz::expectCleanError([&] { readSurfaceGltf(path); });
}
