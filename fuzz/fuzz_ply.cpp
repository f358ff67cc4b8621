// Gaussian PLY files (3DGS's point_cloud.ply layout).
#include "engine/gaussian/ply_gaussians.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  const std::string path = fuzz::writeInput("point_cloud.ply", data, size);
  return fuzz::expectCleanError([&] { readGaussiansPly(path); });
}
