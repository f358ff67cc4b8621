#include "engine/run/checkpoint_format.h"

#include <cstring>
#include <random>
#include <sstream>

#include "engine/base/error.h"
#include "engine/gaussian/gaussians.h"

namespace refrax {
namespace {

constexpr char kMagic[8] = {'R', 'F', 'X', 'C', 'K', 'P', 'T', '\0'};
// Version 2 added the surface gradients summed since the last surface step (--surface-batch);
// version 1 files (every step a surface step) load with those sums at zero.
constexpr uint32_t kVersion = 2;

struct Writer {
  std::string bytes;
  void raw(const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); }
  template <class T>
  void value(const T& v) { raw(&v, sizeof(T)); }
  void section(const void* p, size_t n) {
    value(uint64_t(n));
    raw(p, n);
  }
  template <class T>
  void vec(const std::vector<T>& v) { section(v.data(), v.size() * sizeof(T)); }
  void text(const std::string& s) { section(s.data(), s.size()); }
};

struct Reader {
  const std::string& bytes;
  std::string path;
  size_t at = 0;
  void raw(void* p, size_t n) {
    if (n > bytes.size() - at) fail("checkpoint " + path + " is truncated");
    std::memcpy(p, bytes.data() + at, n);
    at += n;
  }
  template <class T>
  T value() {
    T v;
    raw(&v, sizeof(T));
    return v;
  }
  std::string section() {
    uint64_t n = value<uint64_t>();
    if (n > bytes.size() - at) fail("checkpoint " + path + " is truncated");
    std::string s = bytes.substr(at, n);
    at += n;
    return s;
  }
  // A section of exactly `expected` values (the count checked before anything is allocated).
  template <class T>
  std::vector<T> vec(uint64_t expected, const char* what) {
    std::string s = section();
    if (expected > s.size() / sizeof(T) || s.size() != expected * sizeof(T))
      fail("checkpoint " + path + ": " + what + " holds " + std::to_string(s.size() / sizeof(T)) + " values, expected " +
           std::to_string(expected));
    std::vector<T> v(expected);
    if (!s.empty()) std::memcpy(v.data(), s.data(), s.size());
    return v;
  }
};

}  // namespace

uint32_t checkpointChecksum(const char* data, size_t n) {
  uint32_t h = 2166136261u;
  for (size_t i = 0; i < n; i++) h = (h ^ uint8_t(data[i])) * 16777619u;
  return h;
}

std::string encodeCheckpoint(const CheckpointContents& c) {
  Writer w;
  w.raw(kMagic, 8);
  w.value(kVersion);
  w.text(c.model);
  w.value(c.step);
  w.value(c.trainingSeconds);
  w.text(c.rng);
  w.vec(c.viewOrder);
  w.value(c.viewCursor);
  w.value(c.gaussians);
  w.vec(c.params);
  w.vec(c.adamM);
  w.vec(c.adamV);
  for (int32_t s : c.groupSteps) w.value(s);
  w.vec(c.densifyStats);
  w.value(c.heightCount);
  if (c.heightCount) {
    w.vec(c.heightWeights);
    w.vec(c.heightM);
    w.vec(c.heightV);
    w.value(c.heightStep);
    w.vec(c.heightGrad);
  }
  w.value(c.planeHeight);
  w.value(c.planeM);
  w.value(c.planeV);
  w.value(c.planeStep);
  w.value(c.planeGrad);
  uint32_t sum = checkpointChecksum(w.bytes.data(), w.bytes.size());
  w.value(sum);
  return w.bytes;
}

void verifyCheckpointBytes(const std::string& bytes, const std::string& path) {
  if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 8) != 0) fail("checkpoint " + path + " is not a Refrax checkpoint");
  uint32_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 4, 4);
  if (stored != checkpointChecksum(bytes.data(), bytes.size() - 4)) fail("checkpoint " + path + " is corrupted (checksum mismatch)");
}

CheckpointContents decodeCheckpoint(const std::string& bytes, const std::string& path, const CheckpointShape& shape) {
  verifyCheckpointBytes(bytes, path);
  // The checksum is not part of any section: a section may not run into it.
  const std::string body = bytes.substr(0, bytes.size() - 4);
  Reader r{body, path, 8};
  CheckpointContents c;
  const uint32_t version = r.value<uint32_t>();
  if (version != 1 && version != kVersion) fail("checkpoint " + path + " has an unsupported version");
  c.model = r.section();
  if (c.model != shape.model) fail("checkpoint " + path + " was written by a different water model");
  c.step = r.value<int32_t>();
  if (c.step < 0) fail("checkpoint " + path + " has a negative step");
  c.trainingSeconds = r.value<double>();
  c.rng = r.section();
  std::istringstream rng(c.rng);
  std::mt19937 restored;
  rng >> restored;
  if (rng.fail()) fail("checkpoint " + path + ": unreadable RNG state");
  std::string order = r.section();
  if (order.size() % 4) fail("checkpoint " + path + ": the view order is not a list of view indices");
  c.viewOrder.resize(order.size() / 4);
  if (!order.empty()) std::memcpy(c.viewOrder.data(), order.data(), order.size());
  c.viewCursor = r.value<uint32_t>();
  for (uint32_t v : c.viewOrder)
    if (v >= shape.trainViews) fail("checkpoint " + path + " does not match the dataset's training views");
  if (c.viewCursor > c.viewOrder.size()) fail("checkpoint " + path + ": the view cursor is past the view order");
  c.gaussians = r.value<uint64_t>();
  // every Gaussian takes kGaussianFloats floats three times: a count the file cannot hold is corrupt
  if (c.gaussians > body.size() / (3 * kGaussianFloats * sizeof(float))) fail("checkpoint " + path + ": the Gaussian count is corrupt");
  const uint64_t floats = c.gaussians * kGaussianFloats;
  c.params = r.vec<float>(floats, "the Gaussian table");
  GaussianSet set;
  set.params = c.params;
  validateGaussians(set, "the checkpoint");
  c.adamM = r.vec<float>(floats, "the Gaussian Adam moments");
  c.adamV = r.vec<float>(floats, "the Gaussian Adam moments");
  for (size_t g = 0; g < shape.adamGroups; g++) c.groupSteps.push_back(r.value<int32_t>());
  c.densifyStats = r.vec<float>(c.gaussians * 2, "the densification statistics");
  c.heightCount = r.value<uint64_t>();
  if (c.heightCount != shape.heightCount) fail("checkpoint " + path + " has a different height-field size");
  c.heightGrad.assign(c.heightCount, 0.0f);
  if (c.heightCount) {
    c.heightWeights = r.vec<float>(c.heightCount, "the height-field weights");
    c.heightM = r.vec<float>(c.heightCount, "the height-field Adam moments");
    c.heightV = r.vec<float>(c.heightCount, "the height-field Adam moments");
    c.heightStep = r.value<int32_t>();
    if (version >= 2) c.heightGrad = r.vec<float>(c.heightCount, "the height-field gradient sum");
  }
  c.planeHeight = r.value<double>();
  c.planeM = r.value<double>();
  c.planeV = r.value<double>();
  c.planeStep = r.value<int32_t>();
  c.planeGrad = version >= 2 ? r.value<double>() : 0.0;
  if (r.at != body.size()) fail("checkpoint " + path + " has trailing bytes");
  return c;
}

}  // namespace refrax
