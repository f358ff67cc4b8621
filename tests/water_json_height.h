#pragma once
// The ground-truth height of a `refrax synth` dataset from water.json's parameters alone,
// as a user of the dataset would evaluate it (no Refrax code involved).
#include <cmath>

#include <nlohmann/json.hpp>

namespace refrax::test {

inline double heightFromJson(const nlohmann::json& surface, double x, double y) {
  double h = surface["mean_height"].get<double>();
  for (const auto& w : surface["directional_waves"])
    h += w["amplitude"].get<double>() * std::sin(w["kx"].get<double>() * x + w["ky"].get<double>() * y + w["phase"].get<double>());
  for (const auto& r : surface["radial_ripples"]) {
    double dx = x - r["cx"].get<double>(), dy = y - r["cy"].get<double>(), sigma = r["sigma"].get<double>();
    h += r["amplitude"].get<double>() * std::cos(r["k"].get<double>() * std::hypot(dx, dy)) * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
  }
  return h;
}

}  // namespace refrax::test
