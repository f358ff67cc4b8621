#include "engine/height/grid_height.h"

namespace refrax {

GridHeightField createGridHeightField(Context& ctx, HeightGrid grid) {
  validateHeightGrid(grid);
  GridHeightField f;
  std::vector<float> heights(grid.heights.begin(), grid.heights.end());
  f.heights = createBufferFrom(ctx, heights);
  f.grid = std::move(grid);
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

GridPush gridPush(const GridHeightField& field, uint32_t count) {
  const HeightGrid& g = field.grid;
  return GridPush{{float(g.xMin), float(g.yMin), float(g.xMax), float(g.yMax)}, g.nx, g.ny, count, 0};
}
}  // namespace

HeightSource heightSource(const GridHeightField& field) {
  return pointwiseHeightSource(
      field.pipeline,
      [&field](uint32_t count) {
        const GridPush push = gridPush(field, count);
        const uint8_t* bytes = reinterpret_cast<const uint8_t*>(&push);
        return std::vector<uint8_t>(bytes, bytes + sizeof push);
      },
      &field.heights);
}

}  // namespace refrax
