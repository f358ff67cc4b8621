#pragma once
// PNG images as float channels in [0, 1] (the stored 8-bit values / 255, no gamma
// conversion: training compares stored sRGB values, as NeRF/3DGS do).
#include <string>
#include <vector>

namespace refrax {

struct Image {
  int width = 0, height = 0, channels = 0;  // channels 1..4
  std::vector<float> pixels;                // row-major, interleaved
  float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(size_t(y) * width + x) * channels + c]; }
};

// Any 8-bit PNG or JPEG stb reads; a clear error for other formats, corrupt files and
// headers claiming more pixels than the file could hold.
Image readPng(const std::string& path);
void writePng(const std::string& path, const Image& image);  // values clamped to [0,1], rounded; written atomically
// Whether `path` ends in .png (any case): where a user names the file, a PNG must not be
// written under another image format's name.
bool hasPngExtension(const std::string& path);

}  // namespace refrax
