// CPU double-precision reference of the height field: forward, and the analytic gradient
// with respect to every weight (backpropagation written out plainly, one point at a time).
#include "engine/reference/height_field_ref.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/height/height_encoding.h"
#include "engine/height/height_layers.h"

namespace refrax {

namespace {

void checkWeights(const HeightFieldConfig& c, const std::vector<double>& w) {
  if (w.size() != heightParameterCount(c))
    fail("height reference: " + std::to_string(w.size()) + " weights given, the configuration has " +
         std::to_string(heightParameterCount(c)));
}

// acts[l] = input of weight layer l (acts[0] the encoding), l = 0..hidden; returns the output.
// kink (optional) receives the smallest |pre-activation| of any hidden unit.
double forwardAll(const HeightFieldConfig& c, const std::vector<double>& w, double x, double y, std::vector<std::vector<double>>& acts,
                  double* kink = nullptr) {
  HeightLayers L = heightLayers(c);
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
  HeightLayers L = heightLayers(config);
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

}  // namespace refrax
