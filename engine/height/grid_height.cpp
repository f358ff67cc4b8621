#include "engine/height/grid_height.h"

#include <cmath>

#include "engine/base/error.h"

namespace refrax {

GridHeightField createGridHeightField(Context& ctx, uint32_t nx, uint32_t ny, const double box[4], const std::vector<double>& heights) {
  if (nx < 2 || ny < 2) fail("a height grid needs at least 2 x 2 vertices");
  if (heights.size() != size_t(nx) * ny) fail("a height grid's heights do not match its " + std::to_string(nx) + " x " + std::to_string(ny) + " vertices");
  if (!(box[2] > box[0] && box[3] > box[1])) fail("a height grid's box is empty");
  GridHeightField f;
  f.nx = nx;
  f.ny = ny;
  std::vector<float> values(heights.size());
  for (size_t k = 0; k < heights.size(); k++) {
    if (!std::isfinite(heights[k])) fail("a height grid's heights must be finite");
    values[k] = float(heights[k]);
  }
  for (int c = 0; c < 4; c++) f.box[c] = float(box[c]);
  f.heights = createBufferFrom(ctx, values);
  f.pipeline = createComputePipeline(ctx, "grid_heights", {kStorageBuffer, kStorageBuffer, kStorageBuffer}, 32);
  return f;
}

namespace {
struct GridPush {  // grid_heights.comp's push constants
  float box[4];
  int32_t nx, ny;
  uint32_t count;
  uint32_t pad;
};
static_assert(sizeof(GridPush) == 32, "grid_heights.comp's push constants");
}  // namespace

HeightSource heightSource(const GridHeightField& field) {
  return pointwiseHeightSource(
      field.pipeline,
      [&field](uint32_t count) {
        const GridPush push{{field.box[0], field.box[1], field.box[2], field.box[3]}, int32_t(field.nx), int32_t(field.ny), count, 0};
        const uint8_t* bytes = reinterpret_cast<const uint8_t*>(&push);
        return std::vector<uint8_t>(bytes, bytes + sizeof push);
      },
      &field.heights);
}

}  // namespace refrax
