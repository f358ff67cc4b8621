#pragma once
// CPU double reference of one Adam update (engine/optim/adam.h), torch.optim.Adam's formula.
#include <cmath>
#include <vector>

#include "engine/optim/adam.h"

namespace refrax::ref {

// `step` is t after this update (1 for the first).
inline void adamStep(std::vector<double>& param, std::vector<double>& m, std::vector<double>& v, const std::vector<double>& grad,
                     double lr, int step, const AdamSettings& s = {}) {
  double bc1 = 1.0 - std::pow(s.beta1, step), bc2 = 1.0 - std::pow(s.beta2, step);
  for (size_t i = 0; i < param.size(); i++) {
    m[i] = s.beta1 * m[i] + (1.0 - s.beta1) * grad[i];
    v[i] = s.beta2 * v[i] + (1.0 - s.beta2) * grad[i] * grad[i];
    double mHat = m[i] / bc1, vHat = v[i] / bc2;
    const double agreement = std::min(std::abs(mHat) / (std::sqrt(vHat) + s.epsilon), 1.0);
    param[i] -= lr * mHat / (std::sqrt(vHat) + s.epsilon) * (s.agreementPower > 0 ? std::pow(agreement, s.agreementPower) : 1.0);
  }
}

}  // namespace refrax::ref
