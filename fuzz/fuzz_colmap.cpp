// A COLMAP sparse model: the input is one of its six files (cameras, images or points3D, as
// .txt or .bin: the first byte chooses), beside valid text versions of the other two.
#include <filesystem>

#include "engine/dataset/colmap_model.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace refrax;
  if (size == 0) return 0;
  static const char* kFiles[] = {"cameras.txt", "images.txt", "points3D.txt", "cameras.bin", "images.bin", "points3D.bin"};
  const int which = data[0] % 6;
  const std::string dir = fuzz::scratch() + "/colmap";
  std::filesystem::create_directories(dir);
  for (const char* f : kFiles) std::filesystem::remove(dir + "/" + f);
  auto text = [&](const char* name, const char* content) {
    std::string s(content);
    fuzz::writeInput(std::string("colmap/") + name, reinterpret_cast<const uint8_t*>(s.data()), s.size());
  };
  text("cameras.txt", "1 PINHOLE 64 48 50 50 32 24\n");
  text("images.txt", "1 1 0 0 0 0 0 1 1 a.png\n\n");
  text("points3D.txt", "1 0 0 -1 128 128 128 0.5 1 0\n");
  if (which >= 3) std::filesystem::remove(dir + "/" + std::string(kFiles[which - 3]));
  fuzz::writeInput(std::string("colmap/") + kFiles[which], data + 1, size - 1);
  return fuzz::expectCleanError([&] { readColmapModel(dir); });
}
