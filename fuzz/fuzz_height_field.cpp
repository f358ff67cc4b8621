// height_field.bin. As for checkpoints, the checksum is appended here.
#include "engine/height/height_field_file.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  std::vector<uint8_t> bytes(data, data + size);
  uint32_t h = 2166136261u;  // FNV-1a, as the format's
  for (uint8_t b : bytes) h = (h ^ b) * 16777619u;
  for (int i = 0; i < 4; i++) bytes.push_back(uint8_t(h >> (8 * i)));
  return fuzz::expectCleanError([&] { decodeHeightFieldFile(bytes, "fuzz.bin"); });
}
