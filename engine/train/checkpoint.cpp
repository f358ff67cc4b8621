#include "engine/train/checkpoint.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "engine/error.h"
#include "engine/io/atomic_file.h"
#include "engine/vk_commands.h"
#include "engine/vk_context.h"

namespace refrax {
namespace {

constexpr char kMagic[8] = {'R', 'F', 'X', 'C', 'K', 'P', 'T', '\0'};
// Version 2 added the surface gradients summed since the last surface step (--surface-batch);
// version 1 files (every step a surface step) load with those sums at zero.
constexpr uint32_t kVersion = 2;
constexpr int kKept = 2;

uint32_t fnv1a(const char* data, size_t n) {
  uint32_t h = 2166136261u;
  for (size_t i = 0; i < n; i++) h = (h ^ uint8_t(data[i])) * 16777619u;
  return h;
}

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
    if (at + n > bytes.size()) fail("checkpoint " + path + " is truncated");
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
  template <class T>
  std::vector<T> vec(size_t expected, const char* what) {
    std::string s = section();
    if (s.size() != expected * sizeof(T))
      fail("checkpoint " + path + ": " + what + " holds " + std::to_string(s.size() / sizeof(T)) + " values, expected " +
           std::to_string(expected));
    std::vector<T> v(expected);
    if (!s.empty()) std::memcpy(v.data(), s.data(), s.size());
    return v;
  }
};

int stepOfName(const std::string& name) {
  if (name.rfind("step_", 0) != 0 || name.size() < 11 || name.substr(name.size() - 5) != ".ckpt") return -1;
  std::string digits = name.substr(5, name.size() - 10);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(digits);
}

}  // namespace

std::string checkpointPath(const std::string& runDir, int step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%07d.ckpt", step);
  return (std::filesystem::path(runDir) / "checkpoints" / name).string();
}

std::string latestCheckpoint(const std::string& runDir) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return "";
  int best = -1;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) best = std::max(best, stepOfName(e.path().filename().string()));
  return best < 0 ? "" : checkpointPath(runDir, best);
}

int checkpointStep(const std::string& path) { return stepOfName(std::filesystem::path(path).filename().string()); }

std::string intactCheckpointBefore(const std::string& runDir, int step) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    int k = stepOfName(e.path().filename().string());
    if (k >= 0 && k < step) steps.push_back(k);
  }
  std::sort(steps.rbegin(), steps.rend());
  for (int k : steps) {
    try {
      verifyCheckpointFile(checkpointPath(runDir, k));
      return checkpointPath(runDir, k);
    } catch (const Error&) {
    }
  }
  return "";
}

void saveCheckpoint(TrainSession& s, const std::string& runDir) {
  pushWaterGradient(s);  // the water's pending gradient is saved as the parameters' (heightGrad, planeGrad)
  Context& ctx = *s.ctx;
  Writer w;
  w.raw(kMagic, 8);
  w.value(kVersion);
  w.text(waterModelName(s.config.model));
  w.value(int32_t(s.step));
  w.value(s.trainingSeconds);
  std::ostringstream rng;
  rng << s.rng;
  w.text(rng.str());
  w.vec(s.viewOrder);
  w.value(s.viewCursor);
  w.value(uint64_t(s.gaussians.count()));
  w.vec(s.gaussians.params);
  w.vec(s.gaussianAdam.m);
  w.vec(s.gaussianAdam.v);
  for (const auto& g : s.gaussianAdam.groups) w.value(int32_t(g.step));
  w.vec(s.densifyStats);
  uint64_t heightCount = s.height ? s.height->parameterCount : 0;
  w.value(heightCount);
  if (s.height) {
    w.vec(downloadWeights(ctx, *s.height));
    w.vec(downloadVector<float>(ctx, s.heightAdam.m, heightCount));
    w.vec(downloadVector<float>(ctx, s.heightAdam.v, heightCount));
    w.value(int32_t(s.heightAdam.step));
    w.vec(downloadVector<float>(ctx, s.heightGrad, heightCount));
  }
  w.value(s.planeHeight);
  w.value(s.planeM);
  w.value(s.planeV);
  w.value(int32_t(s.planeStep));
  w.value(s.planeGrad);
  uint32_t sum = fnv1a(w.bytes.data(), w.bytes.size());
  w.value(sum);

  std::filesystem::create_directories(std::filesystem::path(runDir) / "checkpoints");
  writeFileAtomic(checkpointPath(runDir, s.step), w.bytes.data(), w.bytes.size());
  // Keep the newest kKept checkpoints.
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(runDir) / "checkpoints")) {
    int k = stepOfName(e.path().filename().string());
    if (k >= 0) steps.push_back(k);
  }
  std::sort(steps.begin(), steps.end());
  for (size_t i = 0; i + kKept < steps.size(); i++) std::filesystem::remove(checkpointPath(runDir, steps[i]));
}

namespace {

void verifyBytes(const std::string& bytes, const std::string& path) {
  if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 8) != 0) fail("checkpoint " + path + " is not a Refrax checkpoint");
  uint32_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 4, 4);
  if (stored != fnv1a(bytes.data(), bytes.size() - 4)) fail("checkpoint " + path + " is corrupted (checksum mismatch)");
}

}  // namespace

void verifyCheckpointFile(const std::string& path) { verifyBytes(readFile(path), path); }

void loadCheckpoint(TrainSession& s, const std::string& path) {
  std::string bytes = readFile(path);
  verifyBytes(bytes, path);
  Reader r{bytes, path, 8};
  const uint32_t version = r.value<uint32_t>();
  if (version != 1 && version != kVersion) fail("checkpoint " + path + " has an unsupported version");
  if (r.section() != waterModelName(s.config.model)) fail("checkpoint " + path + " was written by a different water model");
  int step = r.value<int32_t>();
  double seconds = r.value<double>();
  std::istringstream rng(r.section());
  std::mt19937 restored;
  rng >> restored;
  if (rng.fail()) fail("checkpoint " + path + ": unreadable RNG state");
  std::string order = r.section();
  std::vector<uint32_t> viewOrder(order.size() / 4);
  if (!order.empty()) std::memcpy(viewOrder.data(), order.data(), viewOrder.size() * 4);
  uint32_t cursor = r.value<uint32_t>();
  size_t trainViews = s.dataset.split("train").size();
  for (uint32_t v : viewOrder)
    if (v >= trainViews) fail("checkpoint " + path + " does not match the dataset's training views");
  uint64_t count = r.value<uint64_t>();
  GaussianSet set;
  set.params = r.vec<float>(count * kGaussianFloats, "the Gaussian table");
  validateGaussians(set, "the checkpoint");
  std::vector<float> m = r.vec<float>(count * kGaussianFloats, "the Gaussian Adam moments");
  std::vector<float> v = r.vec<float>(count * kGaussianFloats, "the Gaussian Adam moments");
  std::vector<int> groupSteps;
  for (size_t g = 0; g < s.gaussianAdam.groups.size(); g++) groupSteps.push_back(r.value<int32_t>());
  std::vector<float> densifyStats = r.vec<float>(count * 2, "the densification statistics");
  uint64_t heightCount = r.value<uint64_t>();
  if (heightCount != (s.height ? s.height->parameterCount : 0)) fail("checkpoint " + path + " has a different height-field size");
  std::vector<float> weights, hm, hv, hg(heightCount, 0.0f);
  int heightStep = 0;
  if (s.height) {
    weights = r.vec<float>(heightCount, "the height-field weights");
    hm = r.vec<float>(heightCount, "the height-field Adam moments");
    hv = r.vec<float>(heightCount, "the height-field Adam moments");
    heightStep = r.value<int32_t>();
    if (version >= 2) hg = r.vec<float>(heightCount, "the height-field gradient sum");
  }
  double planeHeight = r.value<double>(), planeM = r.value<double>(), planeV = r.value<double>();
  int planeStep = r.value<int32_t>();
  double planeGrad = version >= 2 ? r.value<double>() : 0.0;
  if (r.at + 4 != bytes.size()) fail("checkpoint " + path + " has trailing bytes");

  // Everything read and checked: install it.
  Context& ctx = *s.ctx;
  s.step = step;
  s.trainingSeconds = seconds;
  s.rng = restored;
  s.viewOrder = viewOrder;
  s.viewCursor = cursor;
  s.gaussians = std::move(set);
  s.gaussianAdam.m = std::move(m);
  s.gaussianAdam.v = std::move(v);
  for (size_t g = 0; g < groupSteps.size(); g++) s.gaussianAdam.groups[g].step = groupSteps[g];
  syncGaussians(s, true);
  s.densifyStats = std::move(densifyStats);
  if (s.height) {
    uploadWeights(ctx, *s.height, weights);
    s.height->config.encodingWindow = encodingWindowAfterStep(s.config, s.step, surfaceBatchSteps(s));
    upload(ctx, s.heightAdam.m, hm.data(), hm.size() * 4);
    upload(ctx, s.heightAdam.v, hv.data(), hv.size() * 4);
    s.heightAdam.step = heightStep;
    upload(ctx, s.heightGrad, hg.data(), hg.size() * 4);
  }
  s.planeHeight = planeHeight;
  s.planeM = planeM;
  s.planeV = planeV;
  s.planeStep = planeStep;
  s.planeGrad = planeGrad;
  s.plane.waves.base = float(planeHeight);
  if (s.surface) {
    HeightSource src = currentHeightSource(s);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *s.surface, src); });
    if (s.step > s.config.schedule.surfaceFreeze) anchorMeanHeight(s);  // as the uninterrupted run left it
  }
}

}  // namespace refrax
