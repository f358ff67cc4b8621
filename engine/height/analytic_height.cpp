#include "engine/height/analytic_height.h"

#include "engine/height/height_math.h"
#include "engine/vk/vk_buffer.h"

namespace refrax {

AnalyticWaves randomWaves(std::mt19937& rng, float amplitude, float maxWaveNumber) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  AnalyticWaves w;
  w.base = 0.1f * (U(rng) - 0.5f);
  for (auto& k : w.waves) {
    k[0] = amplitude * (0.3f + 0.7f * U(rng)) / 4.0f;
    k[1] = maxWaveNumber * (2 * U(rng) - 1);
    k[2] = maxWaveNumber * (2 * U(rng) - 1);
    k[3] = 6.2831853f * U(rng);
  }
  return w;
}

double analyticHeightRef(const AnalyticWaves& w, double x, double y) {
  auto wave = [&](int k) { return glm::dvec4(w.waves[k][0], w.waves[k][1], w.waves[k][2], w.waves[k][3]); };
  return f64::analyticHeight(x, y, double(w.base), wave(0), wave(1), wave(2), wave(3),
                             glm::dvec4(w.sigma[0], w.sigma[1], w.sigma[2], w.sigma[3]));
}

AnalyticHeightField createAnalyticHeightField(Context& ctx, const AnalyticWaves& waves) {
  AnalyticHeightField f;
  f.waves = waves;
  f.pipeline = createComputePipeline(ctx, "analytic_heights", {kStorageBuffer, kStorageBuffer}, 88);
  return f;
}

namespace {
struct AnalyticPush {  // analytic_heights.comp's push constants
  float waves[4][4];
  float sigmas[4];
  float base;
  uint32_t count;
};
static_assert(sizeof(AnalyticPush) == 88, "analytic_heights.comp's push constants");

AnalyticPush analyticPush(const AnalyticHeightField& field, uint32_t count) {
  AnalyticPush push{};
  for (int k = 0; k < 4; k++)
    for (int c = 0; c < 4; c++) push.waves[k][c] = field.waves.waves[k][c];
  for (int k = 0; k < 4; k++) push.sigmas[k] = field.waves.sigma[k];
  push.base = field.waves.base;
  push.count = count;
  return push;
}
}  // namespace

HeightSource heightSource(const AnalyticHeightField& field) {
  return pointwiseHeightSource(field.pipeline, [&field](uint32_t count) {
    const AnalyticPush push = analyticPush(field, count);
    const uint8_t* bytes = reinterpret_cast<const uint8_t*>(&push);
    return std::vector<uint8_t>(bytes, bytes + sizeof push);
  });
}

}  // namespace refrax
