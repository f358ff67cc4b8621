// water.json, with and without the command line's overrides.
#include "engine/dataset/dataset.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  fuzz::writeInput("water.json", data, size);
  fuzz::expectCleanError([] { loadWaterMetadata(fuzz::scratch()); });
  DatasetOptions o;
  o.ior = 1.2;
  o.domain = Rect{-1, -1, 1, 1};
  return fuzz::expectCleanError([&] { loadWaterMetadata(fuzz::scratch(), o); });
}
