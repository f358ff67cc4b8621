// transforms_train.json (and the same as transforms_test.json) of a Blender dataset. The
// scratch folder holds the seed dataset's images (REFRAX_FUZZ_DATASET, set by scripts/fuzz.sh),
// so a file that names them loads all the way through the image checks.
#include <filesystem>

#include "engine/dataset/dataset.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  namespace fs = std::filesystem;
  if (const char* seed = std::getenv("REFRAX_FUZZ_DATASET"))
    for (const char* split : {"train", "test"})
      if (fs::is_directory(fs::path(seed) / split))
        fs::copy(fs::path(seed) / split, fs::path(refrax::fuzz::scratch()) / split,
                 fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  fuzz::writeInput("transforms_train.json", data, size);
  fuzz::writeInput("transforms_test.json", data, size);
  return fuzz::expectCleanError([] { loadBlenderDataset(fuzz::scratch()); });
}
