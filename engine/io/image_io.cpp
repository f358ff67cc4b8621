#include "engine/io/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

namespace {

bool startsWith(const std::string& bytes, const char* magic, size_t n) { return bytes.size() >= n && bytes.compare(0, n, magic, n) == 0; }

// Debian bookworm's stb_image builds a JPEG Huffman table from its 16 code-length counts
// without checking that they sum to at most 256 symbols (the JPEG limit), and writes past its
// 257-entry table when they do (found by fuzzing: fuzz/fuzz_png.cpp). So every DHT segment is
// checked here first, before stb reads any of the file: the markers are walked from SOI, over
// each scan's entropy-coded data (where 0xFF is followed by 0x00 stuffing, fill or RSTn).
// Returns an empty string, or what is wrong.
std::string jpegHuffmanProblem(const std::string& b) {
  const size_t n = b.size();
  auto byte = [&](size_t i) { return static_cast<unsigned char>(b[i]); };
  size_t i = 2;  // after SOI
  while (i + 1 < n) {
    if (byte(i) != 0xFF) {  // entropy-coded data of a scan: on to the next marker
      i++;
      continue;
    }
    unsigned char m = byte(i + 1);
    if (m == 0xFF || m == 0x00 || (m >= 0xD0 && m <= 0xD7) || m == 0x01) {  // fill, stuffing, RSTn, TEM
      i += m == 0xFF ? 1 : 2;
      continue;
    }
    if (m == 0xD9) return "";  // EOI
    if (i + 3 >= n) return "";  // truncated: stb reports that itself
    size_t length = size_t(byte(i + 2)) << 8 | byte(i + 3);
    if (length < 2) return "a marker segment shorter than its length field";
    size_t body = i + 4, end = std::min(n, i + 2 + length);
    if (m == 0xC4) {  // DHT: tables of (class/id, 16 counts, the symbols)
      for (size_t t = body; t < end;) {
        // stb reads a table's counts past the end of a short file as zeros, and past its
        // segment as the bytes that follow: either way a table cut short is refused here
        if (t + 17 > end) return "a Huffman table cut short";
        unsigned total = 0;
        for (int k = 1; k <= 16; k++) total += byte(t + size_t(k));
        if (total > 256) return "a Huffman table with " + std::to_string(total) + " codes (at most 256)";
        t += 17 + total;
      }
    }
    i = i + 2 + length;
  }
  return "";
}

}  // namespace

Image readPng(const std::string& path) {
  std::string bytes = readFile(path);
  // Only the formats cameras and datasets store. stb also decodes TGA, PSD, PIC, ...,
  // whose headers can claim a huge image that 60 bytes of file then "fill" (found by fuzzing).
  if (!startsWith(bytes, "\x89PNG\r\n\x1a\n", 8) && !startsWith(bytes, "\xff\xd8\xff", 3))
    fail("cannot decode image " + path + ": not a PNG or JPEG file");
  if (startsWith(bytes, "\xff\xd8\xff", 3))
    if (std::string problem = jpegHuffmanProblem(bytes); !problem.empty()) fail("cannot decode image " + path + ": a malformed JPEG (" + problem + ")");
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
