// Height field files' bytes: a little-endian header (magic, version, configuration), the
// weights and a checksum.
#include "engine/height/height_field_file.h"

#include <cstring>

#include "engine/base/error.h"

namespace refrax {

namespace {

constexpr char kMagic[8] = {'R', 'F', 'X', 'H', 'G', 'T', 'F', '\0'};
// Version 2 added the coarse-to-fine encoding window (f32 after the domain); version 1
// files (written before it) load with every octave open.
constexpr uint32_t kVersion = 2;
constexpr size_t headerBytes(uint32_t version) { return 8 + 4 * 4 + (version >= 2 ? 8 : 7) * 4 + 8; }  // magic, 4 u32, 7-8 f32, u64

uint32_t fnv1a(const std::vector<uint8_t>& bytes, size_t n) {
  uint32_t h = 2166136261u;
  for (size_t i = 0; i < n; i++) h = (h ^ bytes[i]) * 16777619u;
  return h;
}

struct Writer {
  std::vector<uint8_t> bytes;
  void u32(uint32_t v) {
    for (int i = 0; i < 4; i++) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; i++) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void f32(float v) {
    uint32_t b;
    std::memcpy(&b, &v, 4);
    u32(b);
  }
};

struct Reader {
  const std::vector<uint8_t>& bytes;
  size_t at = 0;
  uint32_t u32() {
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v |= uint32_t(bytes[at++]) << (8 * i);
    return v;
  }
  uint64_t u64() {
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= uint64_t(bytes[at++]) << (8 * i);
    return v;
  }
  float f32() {
    uint32_t b = u32();
    float v;
    std::memcpy(&v, &b, 4);
    return v;
  }
};

}  // namespace

std::vector<uint8_t> encodeHeightFieldFile(const HeightFieldConfig& c, const std::vector<float>& w) {
  Writer out;
  out.bytes.insert(out.bytes.end(), kMagic, kMagic + 8);
  out.u32(kVersion);
  out.u32(c.octaves);
  out.u32(c.width);
  out.u32(c.hiddenLayers);
  for (float v : {c.leakySlope, c.lastLayerInitRange, c.initialHeight, c.domainMin[0], c.domainMin[1], c.domainMax[0], c.domainMax[1],
                  c.encodingWindow})
    out.f32(v);
  out.u64(w.size());
  for (float v : w) out.f32(v);
  out.u32(fnv1a(out.bytes, out.bytes.size()));
  return out.bytes;
}

HeightFieldFile decodeHeightFieldFile(const std::vector<uint8_t>& bytes, const std::string& path) {
  const std::string what = "height field file '" + path + "'";
  if (bytes.size() < 8) fail(what + " is truncated (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) fail(what + " is not a Refrax height field (bad magic)");
  if (bytes.size() < headerBytes(1) + 4) fail(what + " is truncated (" + std::to_string(bytes.size()) + " bytes)");
  Reader in{bytes, 8};
  uint32_t version = in.u32();
  if (version != 1 && version != kVersion)
    fail(what + " has version " + std::to_string(version) + ", this build reads versions 1 and " + std::to_string(kVersion));
  const size_t header = headerBytes(version);
  if (bytes.size() < header + 4) fail(what + " is truncated (" + std::to_string(bytes.size()) + " bytes)");
  HeightFieldConfig c;
  c.octaves = in.u32();
  c.width = in.u32();
  c.hiddenLayers = in.u32();
  c.leakySlope = in.f32();
  c.lastLayerInitRange = in.f32();
  c.initialHeight = in.f32();
  c.domainMin[0] = in.f32();
  c.domainMin[1] = in.f32();
  c.domainMax[0] = in.f32();
  c.domainMax[1] = in.f32();
  if (version >= 2) c.encodingWindow = in.f32();
  uint64_t count = in.u64();
  try {
    validateHeightFieldConfig(c);
  } catch (const Error& e) {
    fail(what + " has a bad configuration: " + e.what());
  }
  if (count != heightParameterCount(c))
    fail(what + " is corrupt: it declares " + std::to_string(count) + " weights, its configuration needs " +
         std::to_string(heightParameterCount(c)));
  uint64_t expected = header + count * 4 + 4;
  if (bytes.size() < expected) fail(what + " is truncated (" + std::to_string(bytes.size()) + " of " + std::to_string(expected) + " bytes)");
  if (bytes.size() > expected) fail(what + " is corrupt: " + std::to_string(bytes.size() - expected) + " bytes after the end");
  std::vector<float> w(count);
  for (auto& v : w) v = in.f32();
  uint32_t stored = in.u32();
  if (stored != fnv1a(bytes, expected - 4)) fail(what + " is corrupt (checksum mismatch)");
  return {c, std::move(w)};
}

}  // namespace refrax
