// Images through stb (dataset views, PNG inputs).
#include "engine/io/image_io.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  const std::string path = fuzz::writeInput("view.png", data, size);
  return fuzz::expectCleanError([&] { readPng(path); });
}
