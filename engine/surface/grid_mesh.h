#pragma once
// A regular triangle grid over a rectangle [x0,x1]x[y0,y1] with (n+1)x(m+1) vertices, two
// triangles per cell, cells emitted in Morton order (lavapipe's builder keeps input order).
// Vertex (i, j) is at index j*(cellsX+1)+i; triangle 2k and 2k+1 split cell order[k] as
// (a, b, d) and (a, d, c) with a=(i,j), b=(i+1,j), c=(i,j+1), d=(i+1,j+1).
#include <cstdint>
#include <functional>
#include <vector>

namespace refrax {

struct GridMesh {
  uint32_t cellsX = 0, cellsY = 0;
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::vector<float> vertices;     // xyz per vertex
  std::vector<uint32_t> indices;   // 3 per triangle
  std::vector<uint32_t> cellOrder; // cellOrder[k] = j*cellsX+i of the cell behind triangles 2k, 2k+1

  uint32_t vertexCount() const { return (cellsX + 1) * (cellsY + 1); }
  uint32_t triangleCount() const { return 2 * cellsX * cellsY; }
};

// Heights from `height(x, y)` (flat at 0 when empty).
GridMesh makeGridMesh(uint32_t cellsX, uint32_t cellsY, float x0, float y0, float x1, float y1,
                      const std::function<float(float, float)>& height = {});

}  // namespace refrax
