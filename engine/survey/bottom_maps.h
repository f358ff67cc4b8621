#pragma once
// What lies under the water, mapped from a trained model as a surveyor maps a bed (issue 49):
// on a regular grid over the water's domain (its vertices, corners included, as the height
// maps'), a vertical ray from above the water per vertex gives
//   - the bottom's elevation: with the water removed, where the Gaussians' accumulated opacity
//     first reaches one half along the ray (TraceOptions::depthAtOpacity), and the opacity the
//     ray reached; no-data (NaN) where it stays under the half (nothing there to map);
//   - the learned water surface's elevation, and the water depth (surface minus bottom);
//   - a true orthophoto of the bottom (the ray's colour, water removed) and one through the
//     learned water (the same ray refracted at it);
//   - a confidence: how many training views see the water surface above the vertex, and at
//     what incidence (the mean angle of their rays from the vertical).
// Values in the loaded dataset's frame (+z up, metres for the synthetic scenes).
#include <cstdint>
#include <vector>

#include "engine/dataset/dataset.h"
#include "engine/model/model.h"

namespace refrax {

struct BottomGrid {
  uint32_t nx = 0, ny = 0;  // vertices along x and y (at least 2 each)
  Rect box;                 // the corners: vertex (i, j) at x = xMin + i (xMax - xMin) / (nx - 1), y likewise
  double x(uint32_t i) const { return box.xMin + (box.xMax - box.xMin) * double(i) / double(nx - 1); }
  double y(uint32_t j) const { return box.yMin + (box.yMax - box.yMin) * double(j) / double(ny - 1); }
  size_t size() const { return size_t(nx) * ny; }
};

// Every layer row by row from y = yMin (row j), as water_height.npy; the files turn them north up.
struct BottomMaps {
  BottomGrid grid;
  std::vector<float> bottom;     // elevation; NaN where the opacity stays under one half
  std::vector<float> opacity;    // the opacity the vertical ray reached, water removed
  std::vector<float> surface;    // the learned water's elevation (the water height without waves)
  std::vector<float> depth;      // surface - bottom; NaN where the bottom is
  std::vector<float> orthoDry;   // rgb per vertex, water removed
  std::vector<float> orthoWet;   // rgb per vertex, through the learned water
  std::vector<float> views;      // training views that see the water above the vertex
  std::vector<float> incidence;  // their rays' mean angle from the vertical, degrees; NaN where none
};

// The opacity a vertical ray must reach for the bottom to be mapped there.
constexpr float kBottomOpacity = 0.5f;

// The grid the run maps by default: the water's domain on `vertices` x `vertices`.
BottomGrid bottomGridOver(const Rect& domain, uint32_t vertices);

// Traces the grid's vertical rays through `model`; `trainViews` for the confidence.
BottomMaps mapBottom(Model& model, const std::vector<View>& trainViews, const BottomGrid& grid);

}  // namespace refrax
