// Training checkpoints. The input is the file without its checksum, which is appended here:
// a fuzzer that had to forge FNV-1a sums would never get past the first check.
#include <cstring>

#include "engine/run/checkpoint_format.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  uint32_t sum = checkpointChecksum(bytes.data(), bytes.size());
  bytes.append(reinterpret_cast<const char*>(&sum), 4);
  // the seed corpus's run: the refraction model, 8 training views, the 16-wide 1-layer MLP
  CheckpointShape shape{"refraction", 8, 6, 16 * 26 + 16};
  return fuzz::expectCleanError([&] { decodeCheckpoint(bytes, "fuzz.ckpt", shape); });
}
