#pragma once
// CPU double-precision reference of the height field (engine/height/height_field.h): forward,
// and the analytic gradient with respect to every weight, written out plainly one point at a
// time, sharing the encoding with the shaders (engine/height/height_encoding.h).
#include <vector>

#include "engine/height/height_field.h"

namespace refrax {

double heightReference(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y);
void heightReferenceGradient(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y,
                             std::vector<double>& dHdWeights);
// Smallest |pre-activation| over every hidden unit at (x, y): how far the point is from a
// leaky-ReLU kink. Finite differences are only valid for points where a step cannot cross one.
double heightReferenceKinkDistance(const HeightFieldConfig& config, const std::vector<double>& weights, double x, double y);

}  // namespace refrax
