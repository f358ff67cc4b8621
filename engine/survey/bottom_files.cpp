#include "engine/survey/bottom_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/io/geotiff.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/ply_points.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// A layer's values north up (row 0 at yMax), `shift` added to each.
std::vector<float> northUp(const BottomGrid& g, const std::vector<float>& v, size_t perVertex, double shift = 0) {
  std::vector<float> out(v.size());
  for (uint32_t r = 0; r < g.ny; r++)
    for (size_t k = 0; k < g.nx * perVertex; k++) out[r * g.nx * perVertex + k] = float(v[(g.ny - 1 - r) * g.nx * perVertex + k] + shift);
  return out;
}

std::pair<double, double> range(const std::vector<float>& v) {
  double lo = INFINITY, hi = -INFINITY;
  for (float x : v)
    if (std::isfinite(x)) lo = std::min(lo, double(x)), hi = std::max(hi, double(x));
  return {lo, hi};
}

// Low to high: deep blue, cyan, green, yellow, white.
void ramp(double s, float* rgb) {
  static const float stops[5][3] = {{0.05f, 0.1f, 0.45f}, {0.1f, 0.6f, 0.85f}, {0.3f, 0.75f, 0.35f}, {0.95f, 0.85f, 0.3f}, {1, 1, 1}};
  s = std::clamp(s, 0.0, 1.0) * 4.0;
  const int a = std::min(int(s), 3);
  const double f = s - a;
  for (int c = 0; c < 3; c++) rgb[c] = float(stops[a][c] * (1 - f) + stops[a + 1][c] * f);
}

// A metric length of 1, 2 or 5 times a power of ten, at most a quarter of `width`.
double scaleBarLength(double width) {
  const double p = std::pow(10.0, std::floor(std::log10(width / 4)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= width / 4) return m * p;
  return p;
}

// The layer coloured (no-data grey), enlarged to at least 256 px wide, a ramp from its low to its
// high under it, and a white scale bar of `bar` metres at the lower left.
Image preview(const BottomGrid& g, const std::vector<float>& north, double lo, double hi, double bar) {
  const int f = std::max(1, int(256 / g.nx)), w = int(g.nx) * f, h = int(g.ny) * f, rampRows = std::max(8, h / 16);
  Image im;
  im.width = w, im.height = h + 4 + rampRows, im.channels = 3;
  im.pixels.assign(size_t(im.width) * im.height * 3, 0.0f);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      const float v = north[size_t(y / f) * g.nx + size_t(x / f)];
      if (std::isfinite(v)) ramp(hi > lo ? (v - lo) / (hi - lo) : 0.5, &im.at(x, y, 0));
      else im.at(x, y, 0) = im.at(x, y, 1) = im.at(x, y, 2) = 0.5f;
    }
  for (int y = h + 4; y < im.height; y++)
    for (int x = 0; x < w; x++) ramp(double(x) / std::max(1, w - 1), &im.at(x, y, 0));
  const double metresPerPixel = (g.box.xMax - g.box.xMin) / double(w - 1);
  const int barPixels = int(std::lround(bar / metresPerPixel)), y0 = h - 4 - std::max(2, h / 100);
  for (int y = std::max(0, y0); y < h - 4; y++)
    for (int x = 4; x < std::min(w, 4 + barPixels); x++) im.at(x, y, 0) = im.at(x, y, 1) = im.at(x, y, 2) = 1.0f;
  return im;
}

Image rgbImage(const BottomGrid& g, const std::vector<float>& north) {
  Image im;
  im.width = int(g.nx), im.height = int(g.ny), im.channels = 3, im.pixels = north;
  return im;
}

std::vector<uint8_t> bytes(const std::vector<float>& v) {
  std::vector<uint8_t> b(v.size());
  for (size_t k = 0; k < v.size(); k++) b[k] = uint8_t(std::lround(std::clamp(v[k], 0.0f, 1.0f) * 255.0f));
  return b;
}

}  // namespace

nlohmann::json writeBottomFiles(StagedFolder& out, const BottomMaps& maps, const BottomFrame& frame, const nlohmann::json& report) {
  const BottomGrid& g = maps.grid;
  const fs::path p(out.path);
  GeoGrid geo;
  geo.width = g.nx, geo.height = g.ny, geo.epsg = frame.epsg;
  geo.dx = (g.box.xMax - g.box.xMin) / double(g.nx - 1), geo.dy = (g.box.yMax - g.box.yMin) / double(g.ny - 1);
  geo.x0 = g.box.xMin + frame.origin[0], geo.yTop = g.box.yMax + frame.origin[1];
  const std::vector<std::pair<std::string, std::string>> meta = {{"REFRAX_FRAME", frame.description}, {"REFRAX_SAMPLES", "grid vertices (PixelIsPoint)"}};
  nlohmann::json layers;
  const double bar = scaleBarLength(g.box.xMax - g.box.xMin);
  struct Layer {
    const char* name;
    const std::vector<float>* values;
    double shift;
    const char* what;
  };
  for (const Layer& l : {Layer{"bottom_elevation", &maps.bottom, frame.origin[2], "bottom elevation"},
                         Layer{"water_surface", &maps.surface, frame.origin[2], "water surface elevation"},
                         Layer{"water_depth", &maps.depth, 0.0, "water depth"}}) {
    const std::vector<float> north = northUp(g, *l.values, 1, l.shift);
    writeGeoTiffFloat((p / (std::string(l.name) + ".tif")).string(), geo, {{l.what, "m"}}, north, meta);
    const auto [lo, hi] = range(north);
    writePng((p / (std::string(l.name) + ".png")).string(), preview(g, north, lo, hi, bar));
    const size_t noData = size_t(std::count_if(north.begin(), north.end(), [](float v) { return !std::isfinite(v); }));
    layers[l.name] = {{"min", std::isfinite(lo) ? nlohmann::json(lo) : nlohmann::json(nullptr)},
                      {"max", std::isfinite(hi) ? nlohmann::json(hi) : nlohmann::json(nullptr)},
                      {"no_data_vertices", noData}};
  }
  std::vector<float> conf(3 * g.size());
  for (size_t k = 0; k < g.size(); k++) conf[3 * k] = maps.opacity[k], conf[3 * k + 1] = maps.views[k], conf[3 * k + 2] = maps.incidence[k];
  writeGeoTiffFloat((p / "confidence.tif").string(), geo, {{"opacity reached (water removed)", ""}, {"training views that see the water above", ""},
                                                           {"their mean incidence from the vertical", "degree"}},
                    northUp(g, conf, 3), meta);
  for (const auto& [name, rgb] : {std::pair{"ortho_dry", &maps.orthoDry}, std::pair{"ortho_wet", &maps.orthoWet}}) {
    const std::vector<float> north = northUp(g, *rgb, 3);
    writeGeoTiffRgb8((p / (std::string(name) + ".tif")).string(), geo, bytes(north), meta);
    writePng((p / (std::string(name) + ".png")).string(), rgbImage(g, north));
  }
  std::vector<PlyPoint> points;
  for (uint32_t j = 0; j < g.ny; j++)
    for (uint32_t i = 0; i < g.nx; i++) {
      const size_t k = size_t(j) * g.nx + i;
      if (!std::isfinite(maps.bottom[k])) continue;
      PlyPoint q;
      q.position = glm::dvec3(g.x(i) + frame.origin[0], g.y(j) + frame.origin[1], maps.bottom[k] + frame.origin[2]);
      q.colour = glm::dvec3(maps.orthoDry[3 * k], maps.orthoDry[3 * k + 1], maps.orthoDry[3 * k + 2]);
      points.push_back(q);
    }
  writePlyPoints((p / "bottom.ply").string(), points);
  nlohmann::json j = report;
  j["grid"] = {{"vertices", {g.nx, g.ny}},
               {"box", {g.box.xMin, g.box.yMin, g.box.xMax, g.box.yMax}},
               {"cell_size", {geo.dx, geo.dy}},
               {"layout", "every raster north up: row 0 at the box's largest y, column 0 at its smallest x; a value is the field at the grid "
                          "vertex (GeoTIFF PixelIsPoint), so a GIS draws each pixel's area centred on it"}};
  j["frame"] = {{"epsg", frame.epsg}, {"origin", {frame.origin[0], frame.origin[1], frame.origin[2]}}, {"what", frame.description}};
  j["layers"] = layers;
  j["scale_bar_m"] = bar;
  j["bottom_opacity"] = kBottomOpacity;
  j["points"] = points.size();
  writeJson((p / "bottom.json").string(), j);
  out.commit();
  return j;
}

}  // namespace refrax
