#pragma once
// GeoTIFF out: a raster a GIS opens where it lies (GDAL, QGIS), one uncompressed strip,
// little-endian. The samples are points on a regular grid (GTRasterTypeGeoKey = PixelIsPoint:
// a value is the field at its grid point, as water_height.npy's and the synthetic truth's are,
// so a GIS draws each pixel's area centred on it), north up (row 0 is the largest y). The frame
// is the dataset's own, metric and local (a user-defined model type in metres), unless an EPSG
// code of a projected CRS is given, whose coordinates the grid's then are.
#include <cstdint>
#include <string>
#include <vector>

namespace refrax {

struct GeoGrid {
  uint32_t width = 0, height = 0;  // samples east and north-south
  double x0 = 0, yTop = 0;         // the sample at row 0, column 0 (north-west)
  double dx = 0, dy = 0;           // spacing east and south, > 0
  int epsg = 0;                    // 0: the dataset's frame; else a projected CRS
};

struct GeoBand {
  std::string description;  // the band's name, e.g. "bottom elevation"
  std::string unit;         // e.g. "m" (empty: none)
};

// float32, `bands` interleaved per sample, north row first; NaN is no-data (GDAL_NODATA "nan").
// `metadata`: name/value pairs GDAL lists as the dataset's metadata.
void writeGeoTiffFloat(const std::string& path, const GeoGrid& grid, const std::vector<GeoBand>& bands, const std::vector<float>& values,
                       const std::vector<std::pair<std::string, std::string>>& metadata = {});
// 8-bit RGB (an orthophoto), 3 per sample, north row first; no no-data.
void writeGeoTiffRgb8(const std::string& path, const GeoGrid& grid, const std::vector<uint8_t>& rgb,
                      const std::vector<std::pair<std::string, std::string>>& metadata = {});

}  // namespace refrax
