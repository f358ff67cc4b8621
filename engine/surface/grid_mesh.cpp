#include "engine/surface/grid_mesh.h"

#include "engine/base/error.h"
#include "engine/trace/presort.h"

namespace refrax {

GridMesh makeGridMesh(uint32_t cellsX, uint32_t cellsY, float x0, float y0, float x1, float y1,
                      const std::function<float(float, float)>& height) {
  if (cellsX == 0 || cellsY == 0) fail("grid mesh needs at least one cell in each direction");
  if (!(x1 > x0) || !(y1 > y0)) fail("grid mesh domain is empty or inverted");
  GridMesh m;
  m.cellsX = cellsX;
  m.cellsY = cellsY;
  m.x0 = x0;
  m.y0 = y0;
  m.x1 = x1;
  m.y1 = y1;
  m.vertices.resize(size_t(m.vertexCount()) * 3);
  for (uint32_t j = 0; j <= cellsY; j++)
    for (uint32_t i = 0; i <= cellsX; i++) {
      float x = x0 + (x1 - x0) * float(i) / float(cellsX);
      float y = y0 + (y1 - y0) * float(j) / float(cellsY);
      float* v = &m.vertices[(size_t(j) * (cellsX + 1) + i) * 3];
      v[0] = x;
      v[1] = y;
      v[2] = height ? height(x, y) : 0.0f;
    }
  m.cellOrder = mortonCellOrder(cellsX, cellsY);
  m.indices.reserve(size_t(m.triangleCount()) * 3);
  for (uint32_t cell : m.cellOrder) {
    uint32_t i = cell % cellsX, j = cell / cellsX;
    uint32_t a = j * (cellsX + 1) + i, b = a + 1, c = a + cellsX + 1, d = c + 1;
    m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
  }
  return m;
}

}  // namespace refrax
