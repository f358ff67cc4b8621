#include "engine/optim/gaussian_adam.h"

#include <cmath>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"

namespace refrax {

GaussianAdam createGaussianAdam(double extent, int lrSteps, size_t count) {
  struct Columns {
    const char* name;
    uint32_t first, width;
  };
  const Columns columns[] = {{"position", f32::kGaussMean, 3},        {"rotation", f32::kGaussRotation, 4},
                             {"scale", f32::kGaussLogScale, 3},       {"density", f32::kGaussLogitDensity, 1},
                             {"sh_dc", f32::kGaussSH, 3},             {"sh_rest", f32::kGaussSH + 3, 45}};
  GaussianAdam adam;
  for (const auto& c : columns) {
    GaussianAdamGroup g;
    g.name = c.name;
    g.first = c.first;
    g.width = c.width;
    g.lr = referenceLearningRate(c.name, extent);
    g.lr.steps = lrSteps;
    adam.groups.push_back(g);
  }
  adam.m.assign(count * kGaussianFloats, 0.0f);
  adam.v.assign(count * kGaussianFloats, 0.0f);
  return adam;
}

void gaussianAdamStep(GaussianAdam& adam, GaussianSet& set, const std::vector<float>& grads, const AdamSettings& s) {
  size_t n = set.count();
  if (grads.size() != set.params.size() || adam.m.size() != set.params.size()) fail("Gaussian Adam: table sizes differ");
  float b1 = float(s.beta1), b2 = float(s.beta2), eps = float(s.epsilon);
  for (auto& g : adam.groups) {
    g.step++;
    double lr = g.lr.at(g.step);
    float stepSize = float(lr / (1.0 - std::pow(s.beta1, g.step)));
    float invSqrtBc2 = float(1.0 / std::sqrt(1.0 - std::pow(s.beta2, g.step)));
    for (size_t i = 0; i < n; i++) {
      size_t base = i * kGaussianFloats + g.first;
      for (uint32_t c = 0; c < g.width; c++) {
        size_t k = base + c;
        float gr = std::isfinite(grads[k]) ? grads[k] : 0.0f;
        float mi = b1 * adam.m[k] + (1.0f - b1) * gr;
        float vi = b2 * adam.v[k] + (1.0f - b2) * gr * gr;
        adam.m[k] = mi;
        adam.v[k] = vi;
        set.params[k] -= stepSize * mi / (std::sqrt(vi) * invSqrtBc2 + eps);
      }
    }
  }
}

void resetGaussianAdamGroup(GaussianAdam& adam, const std::string& name) {
  for (auto& g : adam.groups) {
    if (g.name != name) continue;
    size_t n = adam.m.size() / kGaussianFloats;
    for (size_t i = 0; i < n; i++)
      for (uint32_t c = 0; c < g.width; c++) adam.m[i * kGaussianFloats + g.first + c] = adam.v[i * kGaussianFloats + g.first + c] = 0.0f;
    g.step = 0;
    return;
  }
  fail("Gaussian Adam: no group '" + name + "'");
}

void remapGaussianAdamRows(GaussianAdam& adam, const std::vector<uint32_t>& sourceRow) {
  size_t old = adam.m.size() / kGaussianFloats;
  std::vector<float> m(sourceRow.size() * kGaussianFloats, 0.0f), v(m.size(), 0.0f);
  for (size_t i = 0; i < sourceRow.size(); i++) {
    if (sourceRow[i] == kNewRow) continue;
    if (sourceRow[i] >= old) fail("Gaussian Adam: source row out of range");
    for (uint32_t c = 0; c < kGaussianFloats; c++) {
      m[i * kGaussianFloats + c] = adam.m[sourceRow[i] * kGaussianFloats + c];
      v[i * kGaussianFloats + c] = adam.v[sourceRow[i] * kGaussianFloats + c];
    }
  }
  adam.m.swap(m);
  adam.v.swap(v);
}

}  // namespace refrax
