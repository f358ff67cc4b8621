#pragma once
// Vector Snell refraction for the synthetic data generator (deliberately not the trainer's).
#include <cmath>
#include <glm/glm.hpp>
#include <optional>

namespace refrax::synth {

// Refracts unit direction d at a surface with unit normal n, where eta = n_from / n_to.
// n may face either way; it is flipped to face the incoming ray. Returns nothing on total
// internal reflection (impossible from air into water).
inline std::optional<glm::dvec3> refractDirection(const glm::dvec3& d, glm::dvec3 n, double eta) {
  double cosIn = -glm::dot(n, d);
  if (cosIn < 0) {
    n = -n;
    cosIn = -cosIn;
  }
  double k = 1 - eta * eta * (1 - cosIn * cosIn);
  if (k < 0) return std::nullopt;
  return glm::normalize(eta * d + (eta * cosIn - std::sqrt(k)) * n);
}

}  // namespace refrax::synth
