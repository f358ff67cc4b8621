#include "engine/io/ply_points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/ply_header.h"

namespace refrax {
namespace {

// One binary little-endian scalar of `type` as a double (this machine is little-endian, as
// every target Refrax builds for).
double binaryScalar(const char* p, const std::string& type) {
  auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return double(v);
  };
  if (type == "char" || type == "int8") return get(int8_t{});
  if (type == "uchar" || type == "uint8") return get(uint8_t{});
  if (type == "short" || type == "int16") return get(int16_t{});
  if (type == "ushort" || type == "uint16") return get(uint16_t{});
  if (type == "int" || type == "int32") return get(int32_t{});
  if (type == "uint" || type == "uint32") return get(uint32_t{});
  if (type == "float" || type == "float32") return get(float{});
  return get(double{});
}

}  // namespace

std::vector<PlyPoint> readPlyPoints(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open the point cloud " + path);
  const std::string where = "point cloud " + path;
  const PlyHeader h = readPlyHeader(in, where, "points");
  int slot[6] = {-1, -1, -1, -1, -1, -1};  // x y z red green blue
  const char* names[6] = {"x", "y", "z", "red", "green", "blue"};
  for (size_t i = 0; i < h.props.size(); i++)
    for (int k = 0; k < 6; k++)
      if (h.props[i].name == names[k]) slot[k] = int(i);
  for (int k = 0; k < 3; k++)
    if (slot[k] < 0) fail(where + " has no vertex property '" + names[k] + "'");
  const bool colour = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
  size_t stride = 0;
  for (const PlyProperty& p : h.props) stride += p.bytes;
  std::vector<double> values(h.props.size());
  std::vector<char> record(stride);
  std::vector<PlyPoint> points;
  points.reserve(h.count);
  for (size_t n = 0; n < h.count; n++) {
    const std::string truncated = where + " is truncated: " + std::to_string(n) + " of " + std::to_string(h.count) + " points present";
    if (h.ascii) {
      std::string line;
      do {
        if (!std::getline(in, line)) fail(truncated);
      } while (line.find_first_not_of(" \t\r") == std::string::npos);
      std::istringstream ls(line);
      for (double& v : values)
        if (!(ls >> v)) fail(where + ": point " + std::to_string(n) + " has fewer values than the header's " + std::to_string(values.size()));
    } else {
      if (!in.read(record.data(), std::streamsize(stride))) fail(truncated);
      size_t offset = 0;
      for (size_t i = 0; i < h.props.size(); i++) {
        values[i] = binaryScalar(record.data() + offset, h.props[i].type);
        offset += h.props[i].bytes;
      }
    }
    PlyPoint p;
    p.position = glm::dvec3(values[size_t(slot[0])], values[size_t(slot[1])], values[size_t(slot[2])]);
    if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z))
      fail(where + ": point " + std::to_string(n) + " has a coordinate that is not a finite number");
    if (colour) {
      const bool bytes = h.props[size_t(slot[3])].bytes == 1;
      for (int c = 0; c < 3; c++) p.colour[c] = values[size_t(slot[3 + c])] / (bytes ? 255.0 : 1.0);
    }
    points.push_back(p);
  }
  return points;
}

void writePlyPoints(const std::string& path, const std::vector<PlyPoint>& points) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by Refrax\nelement vertex " + std::to_string(points.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const PlyPoint& p : points) {
    for (int a = 0; a < 3; a++) {
      const float v = float(p.position[a]);
      out.append(reinterpret_cast<const char*>(&v), 4);
    }
    for (int c = 0; c < 3; c++) out += char(uint8_t(std::lround(std::clamp(p.colour[c], 0.0, 1.0) * 255.0)));
  }
  writeFileAtomic(path, out.data(), out.size());
}

}  // namespace refrax
