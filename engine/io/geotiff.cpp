#include "engine/io/geotiff.h"

#include <cmath>
#include <cstring>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

// TIFF 6.0 field types used here
constexpr uint16_t kAscii = 2, kShort = 3, kLong = 4, kDouble = 12;

struct Entry {
  uint16_t tag, type;
  uint32_t count;
  std::string bytes;  // the value, little-endian; inline when it fits in 4 bytes
};

template <typename T>
std::string pack(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.data(), s.size());  // x86 and ARM hosts are little-endian, as "II" says
  return s;
}
Entry shorts(uint16_t tag, const std::vector<uint16_t>& v) { return {tag, kShort, uint32_t(v.size()), pack(v)}; }
Entry longs(uint16_t tag, const std::vector<uint32_t>& v) { return {tag, kLong, uint32_t(v.size()), pack(v)}; }
Entry doubles(uint16_t tag, const std::vector<double>& v) { return {tag, kDouble, uint32_t(v.size()), pack(v)}; }
Entry ascii(uint16_t tag, const std::string& s) { return {tag, kAscii, uint32_t(s.size() + 1), s + '\0'}; }

std::string xmlEscaped(const std::string& s) {
  std::string o;
  for (char c : s) o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : c == '"' ? "&quot;" : std::string(1, c);
  return o;
}

// GDAL's own metadata tag: the bands' names and units, and the dataset's name/value pairs.
std::string gdalMetadata(const std::vector<GeoBand>& bands, const std::vector<std::pair<std::string, std::string>>& metadata) {
  std::string x = "<GDALMetadata>";
  for (const auto& [k, v] : metadata) x += "<Item name=\"" + xmlEscaped(k) + "\">" + xmlEscaped(v) + "</Item>";
  for (size_t b = 0; b < bands.size(); b++) {
    const std::string s = std::to_string(b);
    x += "<Item name=\"DESCRIPTION\" sample=\"" + s + "\" role=\"description\">" + xmlEscaped(bands[b].description) + "</Item>";
    if (!bands[b].unit.empty()) x += "<Item name=\"UNITTYPE\" sample=\"" + s + "\" role=\"unittype\">" + xmlEscaped(bands[b].unit) + "</Item>";
  }
  return x + "</GDALMetadata>";
}

// Where the samples are: a tie point and pixel scale, and the GeoKeys saying they are points
// in a projected CRS or in the dataset's metric frame (geo_keys: 1024 model type, 1025 raster
// type, 1026 citation, 3072 projected CRS, 3076 linear units, 4099 vertical units; 9001 = metre).
std::vector<Entry> georeference(const GeoGrid& g, std::string& citation) {
  citation = g.epsg ? "EPSG:" + std::to_string(g.epsg) + "|" : "Refrax dataset frame: metres, +z up (out of the water)|";
  std::vector<uint16_t> keys = {1, 1, 0, 0};
  auto key = [&](uint16_t id, uint16_t location, uint16_t count, uint16_t value) { keys.insert(keys.end(), {id, location, count, value}); };
  key(1024, 0, 1, g.epsg ? 1 : 32767);  // projected, or user-defined
  key(1025, 0, 1, 2);                   // RasterPixelIsPoint
  key(1026, 34737, uint16_t(citation.size()), 0);
  if (g.epsg) key(3072, 0, 1, uint16_t(g.epsg));
  key(3076, 0, 1, 9001);
  key(4099, 0, 1, 9001);
  keys[3] = uint16_t((keys.size() - 4) / 4);
  return {doubles(33550, {g.dx, g.dy, 0.0}), doubles(33922, {0, 0, 0, g.x0, g.yTop, 0}), shorts(34735, keys), ascii(34737, citation)};
}

void checkGrid(const std::string& path, const GeoGrid& g, size_t values, size_t perSample) {
  if (g.width == 0 || g.height == 0) fail(path + ": a GeoTIFF needs at least one sample");
  if (!(g.dx > 0 && g.dy > 0 && std::isfinite(g.x0) && std::isfinite(g.yTop))) fail(path + ": the grid's spacing must be positive and its origin finite");
  if (g.epsg < 0 || g.epsg > 65535) fail(path + ": EPSG code " + std::to_string(g.epsg) + " is out of range");
  if (values != size_t(g.width) * g.height * perSample) fail(path + ": the raster holds " + std::to_string(values) + " values, not width x height x bands");
}

// Header, one IFD (tags ascending, as TIFF requires), the out-of-line values, then the strip.
void writeTiff(const std::string& path, std::vector<Entry> entries, const std::string& strip) {
  const uint32_t ifdBytes = 2 + 12 * uint32_t(entries.size()) + 4;
  const uint32_t extra = 8 + ifdBytes;
  std::string ifd, data;
  auto u16 = [](std::string& s, uint16_t v) { s.append(reinterpret_cast<const char*>(&v), 2); };
  auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  uint32_t outOfLine = 0;
  for (const Entry& e : entries) outOfLine += e.bytes.size() > 4 ? uint32_t((e.bytes.size() + 1) & ~size_t(1)) : 0;
  const uint32_t stripOffset = extra + outOfLine;
  u16(ifd, uint16_t(entries.size()));
  for (Entry& e : entries) {
    if (e.tag == 273) e.bytes = pack(std::vector<uint32_t>{stripOffset});
    u16(ifd, e.tag), u16(ifd, e.type), u32(ifd, e.count);
    if (e.bytes.size() <= 4) {
      ifd += e.bytes + std::string(4 - e.bytes.size(), '\0');
    } else {
      u32(ifd, extra + uint32_t(data.size()));
      data += e.bytes;
      if (data.size() % 2) data += '\0';  // values start on a word boundary
    }
  }
  u32(ifd, 0);  // no next IFD
  std::string file = std::string("II") + '\x2a' + '\0';
  u32(file, 8);
  file += ifd + data + strip;
  writeFileAtomic(path, file.data(), file.size());
}

std::vector<Entry> baseEntries(const GeoGrid& g, uint16_t bands, uint16_t bits, uint16_t sampleFormat, uint16_t photometric, size_t stripBytes) {
  return {longs(256, {g.width}),
          longs(257, {g.height}),
          shorts(258, std::vector<uint16_t>(bands, bits)),
          shorts(259, {1}),  // no compression
          shorts(262, {photometric}),
          longs(273, {0}),
          shorts(277, {bands}),
          longs(278, {g.height}),  // one strip
          longs(279, {uint32_t(stripBytes)}),
          shorts(284, {1}),  // interleaved
          shorts(339, std::vector<uint16_t>(bands, sampleFormat))};
}

// Bands beyond the photometric interpretation's (one grey, or RGB's three) are extra samples of
// unspecified meaning, as TIFF requires them to be declared (tag 338, before 339).
void declareExtraSamples(std::vector<Entry>& entries, uint16_t extra) {
  if (extra == 0) return;
  entries.insert(entries.end() - 1, shorts(338, std::vector<uint16_t>(extra, 0)));
}

void writeGeoTiff(const std::string& path, const GeoGrid& g, std::vector<Entry> entries, const std::string& strip, const std::string& metadataXml,
                  bool nanNoData) {
  if (strip.size() > 0xFFFFFFF0u) fail(path + ": the raster is over 4 GiB (a classic TIFF's limit)");
  std::string citation;
  for (Entry& e : georeference(g, citation)) entries.push_back(std::move(e));
  entries.push_back(ascii(42112, metadataXml));
  if (nanNoData) entries.push_back(ascii(42113, "nan"));
  writeTiff(path, std::move(entries), strip);
}

}  // namespace

void writeGeoTiffFloat(const std::string& path, const GeoGrid& grid, const std::vector<GeoBand>& bands, const std::vector<float>& values,
                       const std::vector<std::pair<std::string, std::string>>& metadata) {
  if (bands.empty() || bands.size() > 64) fail(path + ": a float GeoTIFF needs 1 to 64 bands");
  checkGrid(path, grid, values.size(), bands.size());
  const std::string strip = pack(values);
  std::vector<Entry> entries = baseEntries(grid, uint16_t(bands.size()), 32, 3, 1, strip.size());
  declareExtraSamples(entries, uint16_t(bands.size() - 1));
  writeGeoTiff(path, grid, std::move(entries), strip, gdalMetadata(bands, metadata), true);
}

void writeGeoTiffRgb8(const std::string& path, const GeoGrid& grid, const std::vector<uint8_t>& rgb,
                      const std::vector<std::pair<std::string, std::string>>& metadata) {
  checkGrid(path, grid, rgb.size(), 3);
  const std::string strip = pack(rgb);
  writeGeoTiff(path, grid, baseEntries(grid, 3, 8, 1, 2, strip.size()), strip, gdalMetadata({}, metadata), false);
}

}  // namespace refrax
