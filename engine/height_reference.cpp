// CPU double-precision reference of the height field: forward, and the analytic gradient
// with respect to every weight (backpropagation written out plainly, one point at a time).
#include <algorithm>
#include <cmath>
#include <random>

#include "engine/error.h"
#include "engine/height_encoding.h"
#include "engine/height_field.h"

namespace refrax {

uint32_t heightInputCount(const HeightFieldConfig& config) { return f64::heightInputCount(config.octaves); }

uint64_t heightParameterCount(const HeightFieldConfig& config) {
  uint64_t w = config.width, in = heightInputCount(config);
  return w * in + uint64_t(config.hiddenLayers - 1) * w * w + w;
}

void validateHeightFieldConfig(const HeightFieldConfig& c) {
  auto finite = [](float v) { return std::isfinite(v); };
  if (c.width == 0 || c.width > 4096) fail("height field width must be in 1..4096, got " + std::to_string(c.width));
  if (c.hiddenLayers == 0 || c.hiddenLayers > 64)
    fail("height field hiddenLayers must be in 1..64, got " + std::to_string(c.hiddenLayers));
  if (c.octaves > 20) fail("height field octaves must be at most 20, got " + std::to_string(c.octaves));
  if (!finite(c.leakySlope) || c.leakySlope <= 0 || c.leakySlope >= 1)
    fail("height field leakySlope must be in (0, 1), got " + std::to_string(c.leakySlope));
  if (!finite(c.lastLayerInitRange) || c.lastLayerInitRange < 0) fail("height field lastLayerInitRange must be finite and >= 0");
  if (!finite(c.initialHeight)) fail("height field initialHeight must be finite");
  if (heightParameterCount(c) > (uint64_t(1) << 28)) fail("height field has too many weights (" + std::to_string(heightParameterCount(c)) + ")");
  for (int a = 0; a < 2; a++)
    if (!finite(c.domainMin[a]) || !finite(c.domainMax[a]) || !(c.domainMax[a] > c.domainMin[a]))
      fail("height field domain must be finite with domainMax > domainMin on both axes");
  if (!(c.encodingWindow >= 0.0f && c.encodingWindow <= 1.0f))
    fail("height field encodingWindow must be in [0, 1], got " + std::to_string(c.encodingWindow));
}

namespace {

struct Layers {
  uint32_t inputs, width, hidden;
  // Offset of weight layer l (0..hidden; hidden is the output layer) and its input count.
  uint64_t offset(uint32_t l) const { return l == 0 ? 0 : uint64_t(width) * inputs + uint64_t(l - 1) * width * width; }
  uint32_t fanIn(uint32_t l) const { return l == 0 ? inputs : width; }
  uint32_t fanOut(uint32_t l) const { return l == hidden ? 1 : width; }
};

Layers layersOf(const HeightFieldConfig& c) { return {heightInputCount(c), c.width, c.hiddenLayers}; }

void checkWeights(const HeightFieldConfig& c, const std::vector<double>& w) {
  if (w.size() != heightParameterCount(c))
    fail("height reference: " + std::to_string(w.size()) + " weights given, the configuration has " +
         std::to_string(heightParameterCount(c)));
}

// acts[l] = input of weight layer l (acts[0] the encoding), l = 0..hidden; returns the output.
// kink (optional) receives the smallest |pre-activation| of any hidden unit.
double forwardAll(const HeightFieldConfig& c, const std::vector<double>& w, double x, double y, std::vector<std::vector<double>>& acts,
                  double* kink = nullptr) {
  Layers L = layersOf(c);
  f64::real2 u = f64::heightDomainToUnit(f64::real2(x, y), f64::real2(c.domainMin[0], c.domainMin[1]),
                                         f64::real2(c.domainMax[0], c.domainMax[1]));
  acts.assign(L.hidden + 1, {});
  acts[0].resize(L.inputs);
  for (uint32_t i = 0; i < L.inputs; i++) acts[0][i] = f64::heightEncodingFeature(u, i, double(c.encodingWindow) * double(c.octaves));
  for (uint32_t l = 0; l < L.hidden; l++) {
    acts[l + 1].assign(L.width, 0.0);
    const double* W = w.data() + L.offset(l);
    for (uint32_t j = 0; j < L.width; j++) {
      double s = 0;
      for (uint32_t k = 0; k < L.fanIn(l); k++) s += W[uint64_t(j) * L.fanIn(l) + k] * acts[l][k];
      if (kink) *kink = std::min(*kink, std::fabs(s));
      acts[l + 1][j] = f64::heightLeakyRelu(s, double(c.leakySlope));
    }
  }
  const double* Wo = w.data() + L.offset(L.hidden);
  double r = 0;
  for (uint32_t k = 0; k < L.width; k++) r += Wo[k] * acts[L.hidden][k];
  return r + double(c.initialHeight);
}

}  // namespace

double heightReference(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y) {
  checkWeights(config, weights);
  std::vector<std::vector<double>> acts;
  return forwardAll(config, weights, x, y, acts);
}

double heightReferenceKinkDistance(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y) {
  checkWeights(config, weights);
  std::vector<std::vector<double>> acts;
  double kink = INFINITY;
  forwardAll(config, weights, x, y, acts, &kink);
  return kink;
}

void heightReferenceGradient(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y,
                             std::vector<double>& dHdWeights) {
  checkWeights(config, weights);
  Layers L = layersOf(config);
  std::vector<std::vector<double>> acts;
  forwardAll(config, weights, x, y, acts);
  dHdWeights.assign(weights.size(), 0.0);
  double slope = config.leakySlope;
  // delta = dH / d(output of weight layer l), starting at the linear output (1).
  std::vector<double> delta(1, 1.0);
  for (uint32_t l = L.hidden + 1; l-- > 0;) {
    uint32_t in = L.fanIn(l), out = L.fanOut(l);
    const double* W = weights.data() + L.offset(l);
    double* G = dHdWeights.data() + L.offset(l);
    for (uint32_t j = 0; j < out; j++)
      for (uint32_t k = 0; k < in; k++) G[uint64_t(j) * in + k] = delta[j] * acts[l][k];
    if (l == 0) break;
    std::vector<double> next(in, 0.0);  // through layer l's weights, then layer l-1's activation
    for (uint32_t k = 0; k < in; k++) {
      double s = 0;
      for (uint32_t j = 0; j < out; j++) s += W[uint64_t(j) * in + k] * delta[j];
      next[k] = s * f64::heightLeakyReluSlopeAt(acts[l][k], slope);
    }
    delta.swap(next);
  }
}

std::vector<float> initialHeightWeights(const HeightFieldConfig& config, uint32_t seed) {
  validateHeightFieldConfig(config);
  Layers L = layersOf(config);
  std::vector<float> w(heightParameterCount(config));
  std::mt19937 rng(seed);
  // A uniform in [-1, 1) from the top 24 bits of one word: identical on every standard library.
  auto symmetric = [&]() { return float(int32_t(rng() >> 8) - (1 << 23)) * (1.0f / float(1 << 23)); };
  for (uint32_t l = 0; l <= L.hidden; l++) {
    float bound = l == L.hidden ? config.lastLayerInitRange
                                : float(std::sqrt(6.0 / ((1.0 + double(config.leakySlope) * config.leakySlope) * L.fanIn(l))));
    uint64_t n = uint64_t(L.fanIn(l)) * L.fanOut(l);
    for (uint64_t i = 0; i < n; i++) w[L.offset(l) + i] = bound * symmetric();
  }
  return w;
}

}  // namespace refrax
