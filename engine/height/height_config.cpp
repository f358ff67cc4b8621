// The height field's configuration (sizes, validation) and its initial weights, on the host.
#include <cmath>
#include <random>

#include "engine/base/error.h"
#include "engine/height/height_encoding.h"
#include "engine/height/height_field.h"
#include "engine/height/height_layers.h"

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

std::vector<float> initialHeightWeights(const HeightFieldConfig& config, uint32_t seed) {
  validateHeightFieldConfig(config);
  HeightLayers L = heightLayers(config);
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
