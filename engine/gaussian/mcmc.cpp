#include "engine/gaussian/mcmc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/base/portable_random.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/optim/adam.h"  // kNewRow

namespace refrax {
namespace {

double densityOf(const float* g) { return f64::sigmoidOf(double(g[f32::kGaussLogitDensity])); }

// Draws rows with probability proportional to their density, among the live ones.
struct DensitySampler {
  std::vector<uint32_t> rows;
  std::vector<double> cumulative;
  DensitySampler() = default;
  DensitySampler(const GaussianSet& set, double minDensity) {
    double total = 0;
    for (size_t i = 0; i < set.count(); i++) {
      const double o = densityOf(set.at(i));
      if (o < minDensity) continue;
      total += o;
      rows.push_back(uint32_t(i));
      cumulative.push_back(total);
    }
  }
  bool empty() const { return rows.empty(); }
  uint32_t draw(std::mt19937& rng) const {
    const double u = portableUniform(rng) * cumulative.back();
    size_t k = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
    return rows[std::min(k, rows.size() - 1)];
  }
};

// Gives row `source` and its copies (extra of them) their shared density and sigmas; the
// copies are written into `targets` rows of `set` (existing rows or rows appended already).
void shareAmong(GaussianSet& set, uint32_t source, const std::vector<uint32_t>& targets) {
  float* g = set.at(source);
  const int copies = std::min(int(targets.size()) + 1, kMcmcMaxCopies);
  const double o = densityOf(g);
  const double shared = std::clamp(mcmcSharedDensity(o, copies), 1e-6, 1.0 - 1e-6);
  const double factor = mcmcSigmaFactor(o, copies);
  g[f32::kGaussLogitDensity] = float(std::log(shared / (1.0 - shared)));
  if (factor > 0 && std::isfinite(factor))
    for (int a = 0; a < 3; a++) g[f32::kGaussLogScale + a] = float(double(g[f32::kGaussLogScale + a]) + std::log(factor));
  for (uint32_t t : targets) std::copy(g, g + kGaussianFloats, set.at(t));
}

}  // namespace

double mcmcSharedDensity(double density, int copies) { return 1.0 - std::pow(1.0 - density, 1.0 / double(copies)); }

double mcmcSigmaFactor(double density, int copies) {
  const double shared = mcmcSharedDensity(density, copies);
  double sum = 0;
  for (int i = 1; i <= copies; i++) {
    double binomial = 1;  // C(i - 1, j)
    for (int j = 0; j < i; j++) {
      sum += binomial * (j % 2 ? -1.0 : 1.0) * std::pow(shared, j + 1) / std::sqrt(double(j + 1));
      binomial = binomial * double(i - 1 - j) / double(j + 1);
    }
  }
  return density / sum;
}

void validateMcmcConfig(const McmcConfig& c) {
  if (!(c.minDensity >= 0 && c.minDensity < 1)) fail("mcmc: the dead density must be in [0, 1)");
  if (!(c.growFraction >= 0 && c.growFraction <= 1)) fail("mcmc: the growth fraction must be in [0, 1]");
  if (!(c.noiseScale >= 0) || !(c.noiseSharpness >= 0)) fail("mcmc: the noise's scale and sharpness must be >= 0");
  if (c.maxGaussians == 0) fail("mcmc: maxGaussians must be at least 1");
}

McmcStats mcmcDensify(GaussianSet& set, const McmcConfig& config, std::mt19937& rng, std::vector<uint32_t>& rowMap) {
  auto start = std::chrono::steady_clock::now();
  validateMcmcConfig(config);
  const size_t n = set.count();
  McmcStats out;
  out.before = out.after = uint32_t(n);
  rowMap.resize(n);
  for (size_t i = 0; i < n; i++) rowMap[i] = uint32_t(i);

  // Relocation: each dead row takes a copy of a live one.
  {
    DensitySampler live(set, config.minDensity);
    if (live.empty()) return out;
    std::vector<std::vector<uint32_t>> copiesOf(n);
    for (size_t i = 0; i < n; i++)
      if (densityOf(set.at(i)) < config.minDensity) copiesOf[live.draw(rng)].push_back(uint32_t(i)), out.relocated++;
    for (size_t s = 0; s < n; s++)
      if (!copiesOf[s].empty()) {
        shareAmong(set, uint32_t(s), copiesOf[s]);
        rowMap[s] = kNewRow;
        for (uint32_t t : copiesOf[s]) rowMap[t] = kNewRow;
      }
  }

  // Growth: growFraction more rows, copies of live ones (as relocated).
  const size_t target = std::min<size_t>(config.maxGaussians, n + size_t(std::floor(double(n) * config.growFraction)));
  // The sampler is built only when there is room: at the cap (the default) growth is a no-op.
  // Shared densities may have fallen under the dead line, so it is drawn afresh.
  const DensitySampler live = target > n ? DensitySampler(set, config.minDensity) : DensitySampler();
  if (!live.empty()) {
    std::vector<std::vector<uint32_t>> copiesOf(n);
    for (size_t row = n; row < target; row++) copiesOf[live.draw(rng)].push_back(uint32_t(row));
    set.params.resize(target * kGaussianFloats);
    rowMap.resize(target, kNewRow);
    for (size_t s = 0; s < n; s++)
      if (!copiesOf[s].empty()) {
        shareAmong(set, uint32_t(s), copiesOf[s]);
        rowMap[s] = kNewRow;
      }
    out.added = uint32_t(target - n);
  }
  out.after = uint32_t(set.count());
  out.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void mcmcPositionNoise(GaussianSet& set, const McmcConfig& config, double positionLr, std::mt19937& rng) {
  validateMcmcConfig(config);
  const double scale = positionLr * double(config.noiseScale);
  for (size_t i = 0; i < set.count(); i++) {
    float* g = set.at(i);
    const double gate = f64::sigmoidOf(double(config.noiseSharpness) * (double(config.minDensity) - densityOf(g)));
    const float* q = g + f32::kGaussRotation;
    const glm::dmat3 R = f64::rotationOf(glm::dvec4(q[0], q[1], q[2], q[3]));
    glm::dvec3 z, variance;
    for (int a = 0; a < 3; a++) {
      z[a] = standardNormal(rng);
      variance[a] = std::exp(2.0 * double(g[f32::kGaussLogScale + a]));
    }
    // R S^2 R^T z, in the Gaussian's own axes and back
    const glm::dvec3 step = R * (variance * (glm::transpose(R) * z)) * (scale * gate);
    for (int a = 0; a < 3; a++) g[f32::kGaussMean + a] = float(double(g[f32::kGaussMean + a]) + step[a]);
  }
}

}  // namespace refrax
