// File IO: atomic writes, PNG, .npy and JSON round trips and their errors on bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include <stb/stb_image_write.h>
#include "tests/gpu_test.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("refrax-test-" + std::to_string(test::freshSeed()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};
}  // namespace

TEST_CASE("atomic writes leave no temporary files and replace the target whole") {
  TempDir dir;
  writeTextAtomic(dir / "a.txt", "first");
  writeTextAtomic(dir / "a.txt", "second, longer");
  CHECK(readFile(dir / "a.txt") == "second, longer");
  int files = 0;
  for (auto& e : fs::directory_iterator(dir.path)) files += e.is_regular_file();
  CHECK(files == 1);
  CHECK_THROWS_AS(writeTextAtomic(dir / "no-such-dir/a.txt", "x"), Error);
  CHECK_THROWS_AS(readFile(dir / "missing.txt"), Error);
}

TEST_CASE("PNG round trip keeps 8-bit values exactly") {
  TempDir dir;
  std::mt19937 rng(test::freshSeed());
  for (int channels : {1, 3, 4}) {
    Image img;
    img.width = 17;
    img.height = 9;
    img.channels = channels;
    img.pixels.resize(size_t(17) * 9 * channels);
    for (auto& v : img.pixels) v = float(rng() % 256) / 255.0f;
    writePng(dir / "img.png", img);
    Image back = readPng(dir / "img.png");
    CHECK(back.width == 17);
    CHECK(back.height == 9);
    CHECK(back.channels == channels);
    CHECK(back.pixels == img.pixels);
  }
  writeTextAtomic(dir / "bad.png", "not a png at all");
  CHECK_THROWS_AS(readPng(dir / "bad.png"), Error);
  CHECK_THROWS_AS(readPng(dir / "missing.png"), Error);
}

TEST_CASE("images: JPEG reads, other formats and impossible headers are refused by name") {
  TempDir dir;
  // A JPEG of a flat grey square decodes close to its value.
  std::vector<unsigned char> grey(16 * 16 * 3, 128);
  std::string jpeg;
  auto sink = [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size); };
  REQUIRE(stbi_write_jpg_to_func(sink, &jpeg, 16, 16, 3, grey.data(), 95));
  writeFileAtomic(dir / "grey.jpg", jpeg.data(), jpeg.size());
  Image img = readPng(dir / "grey.jpg");
  CHECK(img.width == 16);
  CHECK(img.channels == 3);
  CHECK(std::abs(img.at(7, 7, 1) - 128.0f / 255.0f) < 3.0f / 255.0f);

  // The TGA header the PNG fuzzer found (74 bytes): stb "decodes" it to a huge image of filler.
  const unsigned char tga[] = {0x00, 0x00, 0x0a, 0xe1, 0xf3, 0x7f, 0x66, 0xca, 0x5c, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20, 0x20};
  std::string tgaBytes(reinterpret_cast<const char*>(tga), sizeof(tga));
  tgaBytes += std::string(58, ' ');
  writeFileAtomic(dir / "fuzz.png", tgaBytes.data(), tgaBytes.size());
  CHECK_THROWS_WITH_AS(readPng(dir / "fuzz.png"), doctest::Contains("not a PNG or JPEG"), Error);

  // The JPEG the PNG fuzzer found next (24 bytes): a Huffman table of more than 256 codes,
  // which Debian's stb writes past the end of its table for.
  const unsigned char dht[] = {0xff, 0xd8, 0xff, 0xc4, 0xa4, 0x10, 0x00, 0x00, 0x00, 0x7d, 0x0a, 0x0a,
                               0x0a, 0x0a, 0x0a, 0x0a, 0x07, 0xf1, 0x1c, 0x02, 0x0a, 0x0a, 0x0a, 0x0a};
  writeFileAtomic(dir / "dht.jpg", reinterpret_cast<const char*>(dht), sizeof(dht));
  CHECK_THROWS_WITH_AS(readPng(dir / "dht.jpg"), doctest::Contains("dht.jpg: a malformed JPEG (a Huffman table with"), Error);
  // And one cut short (14 bytes): stb reads the missing counts as zeros after 0xff, 0xff, 0xff.
  const unsigned char cut[] = {0xff, 0xd8, 0xff, 0xc4, 0xdb, 0x06, 0x00, 0x00, 0xff, 0xff, 0xff, 0x00, 0x00, 0x25};
  writeFileAtomic(dir / "cut.jpg", reinterpret_cast<const char*>(cut), sizeof(cut));
  CHECK_THROWS_WITH_AS(readPng(dir / "cut.jpg"), doctest::Contains("cut.jpg: a malformed JPEG (a Huffman table cut short)"), Error);

  // A real PNG whose header is edited to claim 8000 x 8000 pixels (which stb
  // itself would allocate, and fill from a few bytes).
  Image small;
  small.width = small.height = 4;
  small.channels = 1;
  small.pixels.assign(16, 0.5f);
  writePng(dir / "small.png", small);
  std::string png = readFile(dir / "small.png");
  for (int field : {16, 20}) {  // IHDR width and height, big-endian
    png[field] = 0, png[field + 1] = 0, png[field + 2] = 0x1f, png[field + 3] = 0x40;
  }
  writeFileAtomic(dir / "huge.png", png.data(), png.size());
  CHECK_THROWS_WITH_AS(readPng(dir / "huge.png"), doctest::Contains("8000x8000"), Error);
}

TEST_CASE(".npy round trip and malformed files") {
  TempDir dir;
  NpyArray a;
  a.shape = {3, 17};
  for (int i = 0; i < 51; i++) a.data.push_back(i * 0.25 - 3);
  writeNpy(dir / "a.npy", a);
  NpyArray b = readNpy(dir / "a.npy");
  CHECK(b.shape == a.shape);
  CHECK(b.data == a.data);
  writeNpy(dir / "d.npy", a, true);
  CHECK(readNpy(dir / "d.npy").data == a.data);
  std::string bytes = readFile(dir / "a.npy");
  writeFileAtomic(dir / "trunc.npy", bytes.data(), bytes.size() - 4);
  CHECK_THROWS_WITH_AS(readNpy(dir / "trunc.npy"), doctest::Contains("the shape needs"), Error);
  writeTextAtomic(dir / "junk.npy", "hello");
  CHECK_THROWS_AS(readNpy(dir / "junk.npy"), Error);
}

TEST_CASE("JSON errors name the file and the field") {
  TempDir dir;
  writeTextAtomic(dir / "bad.json", "{\"a\": [1, 2,, 3]}");
  CHECK_THROWS_WITH_AS(readJson(dir / "bad.json"), doctest::Contains("malformed JSON"), Error);
  writeJson(dir / "ok.json", {{"x", 1.5}, {"s", "text"}});
  auto j = readJson(dir / "ok.json");
  CHECK(requireNumber(j, "x", "ok.json") == 1.5);
  CHECK_THROWS_WITH_AS(requireNumber(j, "s", "ok.json"), doctest::Contains("'s' must be a number"), Error);
  CHECK_THROWS_WITH_AS(requireField(j, "y", "ok.json"), doctest::Contains("missing 'y'"), Error);
}

TEST_CASE("JSON numbers out of range are a clear error, not an escaped exception") {
  TempDir dir;
  writeTextAtomic(dir / "big.json", "{\"x\": 1e999}");
  CHECK_THROWS_WITH_AS(readJson(dir / "big.json"), doctest::Contains("malformed JSON"), Error);
}
