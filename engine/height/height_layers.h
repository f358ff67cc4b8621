#pragma once
// The height-field MLP's weight layout (engine/height/height_field.h): one flat array, weight
// layer l = 0..hidden (hidden is the linear output layer) row-major [fanOut][fanIn], shared by
// the initialiser and the CPU reference (engine/reference/height_field_ref.cpp).
#include <cstdint>

#include "engine/height/height_field.h"

namespace refrax {

struct HeightLayers {
  uint32_t inputs, width, hidden;
  // Offset of weight layer l (0..hidden; hidden is the output layer) and its input count.
  uint64_t offset(uint32_t l) const { return l == 0 ? 0 : uint64_t(width) * inputs + uint64_t(l - 1) * width * width; }
  uint32_t fanIn(uint32_t l) const { return l == 0 ? inputs : width; }
  uint32_t fanOut(uint32_t l) const { return l == hidden ? 1 : width; }
};

inline HeightLayers heightLayers(const HeightFieldConfig& c) { return {heightInputCount(c), c.width, c.hiddenLayers}; }

}  // namespace refrax
