// .npy arrays (LLFF poses_bounds.npy, ground-truth height maps), and an N x 17 array on into
// the LLFF camera conventions (image size taken from its first pose, so valid poses get through).
#include "engine/dataset/dataset.h"
#include "engine/io/npy.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  return fuzz::expectCleanError([&] {
    NpyArray a = parseNpy(std::string(reinterpret_cast<const char*>(data), size), "fuzz.npy");
    if (a.shape.size() != 2 || a.shape[1] != 17 || a.shape[0] == 0) return;
    double h = a.data[4], w = a.data[9];
    if (!(h >= 1 && h <= 8192 && w >= 1 && w <= 8192)) return;
    llffCameras(a.data, a.shape[0], 1, int(w), int(h), "fuzz.npy");
    llffCameras(a.data, a.shape[0], 1, int(w), int(h), "fuzz.npy", true);
  });
}
