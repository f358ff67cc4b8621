#pragma once
// The mapped bottom as a surveyor's deliverables (refrax export RUN --bottom DIR), every raster
// north up on the grid's vertices (GeoTIFF PixelIsPoint, engine/io/geotiff.h), in the dataset's
// frame or, given an EPSG code and an origin, in that projected CRS (x, y and z shifted by it):
//   bottom_elevation.tif  float32, NaN no-data: the bottom's z
//   water_surface.tif     float32: the learned water's z
//   water_depth.tif       float32, NaN no-data: surface minus bottom
//   confidence.tif        float32 x 3: the opacity reached, the views that see the vertex, their mean incidence (degrees)
//   ortho_dry.tif, ortho_wet.tif   8-bit RGB: the true orthophoto with the water removed / kept
//   *.png                 previews: each float layer coloured (a ramp from low to high under it,
//                         no-data grey, a white scale bar of `scale_bar_m` metres at the lower left), the orthophotos
//   bottom.ply            the mapped vertices as coloured points (the dry orthophoto's colours)
//   bottom.json           the grid, frame, files, each layer's range and the accuracy against the truth
// The folder appears whole or not at all (engine/io/staged_folder.h).
#include <string>

#include <nlohmann/json.hpp>

#include "engine/io/staged_folder.h"
#include "engine/survey/bottom_maps.h"

namespace refrax {

struct BottomFrame {
  int epsg = 0;                         // 0: the dataset's frame
  double origin[3] = {0, 0, 0};         // added to x, y, z (the dataset frame's origin in the CRS)
  std::string description = "the dataset's frame, +z up";
};

// Writes into `folder` and commits it; `report`: what to add to bottom.json (the run, the
// accuracy); returns bottom.json's content.
nlohmann::json writeBottomFiles(StagedFolder& folder, const BottomMaps& maps, const BottomFrame& frame, const nlohmann::json& report);

}  // namespace refrax
