#include "engine/io/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

namespace {

bool startsWith(const std::string& bytes, const char* magic, size_t n) { return bytes.size() >= n && bytes.compare(0, n, magic, n) == 0; }

}  // namespace

Image readPng(const std::string& path) {
  std::string bytes = readFile(path);
  // Only the formats cameras and datasets store. stb also decodes TGA, PSD, PIC, ...,
  // whose headers can claim a huge image that 60 bytes of file then "fill" (found by fuzzing).
  if (!startsWith(bytes, "\x89PNG\r\n\x1a\n", 8) && !startsWith(bytes, "\xff\xd8\xff", 3))
    fail("cannot decode image " + path + ": not a PNG or JPEG file");
  const auto* raw = reinterpret_cast<const unsigned char*>(bytes.data());
  int w = 0, h = 0, c = 0;
  if (!stbi_info_from_memory(raw, int(bytes.size()), &w, &h, &c))
    fail("cannot decode image " + path + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown format"));
  // A truncated JPEG decodes to a full image of filler, so a header's size alone
  // cannot be trusted: deflate cannot compress past 1032:1 and a flat JPEG block takes
  // a few bits per 64 pixels, so no real file holds more than kMaxPixelsPerByte.
  constexpr double kMaxPixelsPerByte = 4096, kMaxPixels = double(1 << 28);
  const double pixels = double(w) * h;
  if (pixels > kMaxPixels || pixels > kMaxPixelsPerByte * double(bytes.size()))
    fail("cannot decode image " + path + ": its header claims " + std::to_string(w) + "x" + std::to_string(h) +
         " pixels, more than a " + std::to_string(bytes.size()) + "-byte file can hold");
  unsigned char* data = stbi_load_from_memory(raw, int(bytes.size()), &w, &h, &c, 0);
  if (!data) fail("cannot decode image " + path + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown format"));
  Image img;
  img.width = w;
  img.height = h;
  img.channels = c;
  img.pixels.resize(size_t(w) * h * c);
  for (size_t i = 0; i < img.pixels.size(); i++) img.pixels[i] = data[i] / 255.0f;
  stbi_image_free(data);
  return img;
}

void writePng(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != size_t(image.width) * image.height * image.channels)
    fail("writePng: malformed image for " + path);
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); i++) {
    float v = image.pixels[i];
    v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
  }
  std::string encoded;
  auto sink = [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size); };
  if (!stbi_write_png_to_func(sink, &encoded, image.width, image.height, image.channels, bytes.data(),
                              image.width * image.channels))
    fail("cannot encode PNG " + path);
  writeFileAtomic(path, encoded.data(), encoded.size());
}

bool hasPngExtension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

}  // namespace refrax
