#include "engine/dataset/colmap_model.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

// COLMAP's camera models by id (src/colmap/sensor/models.h), with their parameter counts.
struct ModelInfo {
  const char* name;
  size_t params;
};
const ModelInfo kModels[] = {{"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},        {"SIMPLE_RADIAL", 4},         {"RADIAL", 5},
                             {"OPENCV", 8},         {"OPENCV_FISHEYE", 8}, {"FULL_OPENCV", 12},          {"FOV", 5},
                             {"SIMPLE_RADIAL_FISHEYE", 4}, {"RADIAL_FISHEYE", 5}, {"THIN_PRISM_FISHEYE", 12}};
constexpr int kModelCount = int(sizeof(kModels) / sizeof(kModels[0]));
constexpr uint64_t kMaxCount = 1u << 24;  // cameras, images, points or a track: more is not a file COLMAP wrote
constexpr uint64_t kMaxSide = 1u << 16;   // image side in pixels

int modelId(const std::string& name) {
  for (int i = 0; i < kModelCount; i++)
    if (name == kModels[i].name) return i;
  return -1;
}

// ---- binary: little-endian, as COLMAP writes on every platform it supports

struct Reader {
  const std::string& bytes;
  const std::string& path;
  size_t at = 0;
  template <class T>
  T get() {
    if (bytes.size() - at < sizeof(T)) fail(path + ": truncated (a COLMAP binary file ends early)");
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  std::string string() {
    size_t end = bytes.find('\0', at);
    if (end == std::string::npos) fail(path + ": truncated (an image name without its terminating zero)");
    std::string s = bytes.substr(at, end - at);
    at = end + 1;
    return s;
  }
  uint64_t count(const char* what) {
    uint64_t n = get<uint64_t>();
    if (n > kMaxCount) fail(path + ": " + std::to_string(n) + " " + what + " (more than a COLMAP model holds)");
    return n;
  }
};

struct Writer {
  std::string bytes;
  template <class T>
  void put(T v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
};

void checkCamera(const ColmapCamera& c, const std::string& path) {
  if (c.width == 0 || c.height == 0 || c.width > kMaxSide || c.height > kMaxSide)
    fail(path + ": camera " + std::to_string(c.id) + " has an image size of " + std::to_string(c.width) + " x " + std::to_string(c.height));
  for (double p : c.params)
    if (!std::isfinite(p)) fail(path + ": camera " + std::to_string(c.id) + " has a non-finite parameter");
}

void checkImage(const ColmapImage& im, const std::string& path) {
  const std::string which = path + ": image " + std::to_string(im.id) + " (" + im.name + ")";
  for (int k = 0; k < 4; k++)
    if (!std::isfinite(im.q[k])) fail(which + " has a non-finite rotation");
  for (int k = 0; k < 3; k++)
    if (!std::isfinite(im.t[k])) fail(which + " has a non-finite position");
  double norm = glm::length(im.q);
  if (std::abs(norm - 1.0) > 1e-3) fail(which + ": its rotation quaternion has length " + std::to_string(norm) + ", not 1");
  if (im.name.empty() || im.name.find("..") != std::string::npos || im.name[0] == '/')
    fail(which + ": the image name must be a path inside the image folder");
}

std::map<uint32_t, ColmapCamera> readCamerasBinary(const std::string& path) {
  std::string bytes = readFile(path);
  Reader r{bytes, path};
  std::map<uint32_t, ColmapCamera> cameras;
  for (uint64_t n = r.count("cameras"), i = 0; i < n; i++) {
    ColmapCamera c;
    c.id = r.get<uint32_t>();
    int32_t model = r.get<int32_t>();
    if (model < 0 || model >= kModelCount) fail(path + ": camera " + std::to_string(c.id) + " has an unknown model id " + std::to_string(model));
    c.model = kModels[model].name;
    c.width = r.get<uint64_t>();
    c.height = r.get<uint64_t>();
    for (size_t k = 0; k < kModels[model].params; k++) c.params.push_back(r.get<double>());
    checkCamera(c, path);
    if (!cameras.emplace(c.id, c).second) fail(path + ": camera " + std::to_string(c.id) + " appears twice");
  }
  if (r.at != bytes.size()) fail(path + ": " + std::to_string(bytes.size() - r.at) + " bytes after the last camera");
  return cameras;
}

std::vector<ColmapImage> readImagesBinary(const std::string& path) {
  std::string bytes = readFile(path);
  Reader r{bytes, path};
  std::vector<ColmapImage> images;
  for (uint64_t n = r.count("images"), i = 0; i < n; i++) {
    ColmapImage im;
    im.id = r.get<uint32_t>();
    for (int k = 0; k < 4; k++) im.q[k] = r.get<double>();
    for (int k = 0; k < 3; k++) im.t[k] = r.get<double>();
    im.cameraId = r.get<uint32_t>();
    im.name = r.string();
    uint64_t points = r.count("2D points");
    if (bytes.size() - r.at < points * 24) fail(path + ": truncated (an image's 2D points end early)");
    r.at += points * 24;  // x, y, point3D id: the loader needs none of them
    checkImage(im, path);
    images.push_back(im);
  }
  if (r.at != bytes.size()) fail(path + ": " + std::to_string(bytes.size() - r.at) + " bytes after the last image");
  return images;
}

std::vector<ColmapPoint> readPointsBinary(const std::string& path) {
  std::string bytes = readFile(path);
  Reader r{bytes, path};
  std::vector<ColmapPoint> points;
  for (uint64_t n = r.count("points"), i = 0; i < n; i++) {
    ColmapPoint p;
    r.get<uint64_t>();  // id
    for (int k = 0; k < 3; k++) p.position[k] = r.get<double>();
    for (int k = 0; k < 3; k++) p.colour[k] = r.get<uint8_t>() / 255.0;
    p.error = r.get<double>();
    uint64_t track = r.count("track entries");
    if (bytes.size() - r.at < track * 8) fail(path + ": truncated (a point's track ends early)");
    r.at += track * 8;
    p.views = uint32_t(track);
    for (int k = 0; k < 3; k++)
      if (!std::isfinite(p.position[k])) fail(path + ": a point has a non-finite position");
    points.push_back(p);
  }
  if (r.at != bytes.size()) fail(path + ": " + std::to_string(bytes.size() - r.at) + " bytes after the last point");
  return points;
}

// ---- text: '#' comments, one record per line (images: two lines each)

// A data line and its line number in the file (1-based), so every error points at the line
// an editor shows.
struct TextLine {
  size_t number;
  std::string text;
};

std::vector<TextLine> dataLines(const std::string& path, bool keepEmpty) {
  std::stringstream in(readFile(path));
  std::vector<TextLine> lines;
  std::string line;
  for (size_t number = 1; std::getline(in, line); number++) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '#') continue;
    if (line.empty() && !keepEmpty) continue;
    lines.push_back({number, line});
  }
  return lines;
}

// Whether `line` can be an image's POINTS2D line: empty, or (X, Y, POINT3D_ID) triples of
// numbers. An image line (ID, QW..TZ, CAMERA_ID, NAME: ten fields, the name not a number)
// cannot, so a file that leaves the POINTS2D lines out is caught instead of read as every
// other image.
bool isPointsLine(const std::string& line) {
  std::istringstream in(line);
  std::string token;
  size_t count = 0;
  while (in >> token) {
    char* end = nullptr;
    std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end) return false;
    count++;
  }
  return count % 3 == 0;
}

template <class T>
T field(std::istringstream& in, const std::string& path, size_t line, const char* what) {
  T v{};
  if (!(in >> v)) fail(path + ": line " + std::to_string(line) + ": expected " + what);
  return v;
}

std::map<uint32_t, ColmapCamera> readCamerasText(const std::string& path) {
  std::map<uint32_t, ColmapCamera> cameras;
  for (const auto& [n, line] : dataLines(path, false)) {
    std::istringstream in(line);
    ColmapCamera c;
    c.id = field<uint32_t>(in, path, n, "a camera id");
    c.model = field<std::string>(in, path, n, "a camera model");
    c.width = field<uint64_t>(in, path, n, "the image width");
    c.height = field<uint64_t>(in, path, n, "the image height");
    double p;
    while (in >> p) c.params.push_back(p);
    if (!in.eof()) fail(path + ": line " + std::to_string(n) + ": a camera parameter is not a number");
    size_t expected = colmapParamCount(c.model);
    if (expected == 0) fail(path + ": camera " + std::to_string(c.id) + " has an unknown model '" + c.model + "'");
    if (c.params.size() != expected)
      fail(path + ": camera " + std::to_string(c.id) + " (" + c.model + ") has " + std::to_string(c.params.size()) + " parameters, the model has " +
           std::to_string(expected));
    checkCamera(c, path);
    if (!cameras.emplace(c.id, c).second) fail(path + ": camera " + std::to_string(c.id) + " appears twice");
  }
  return cameras;
}

std::vector<ColmapImage> readImagesText(const std::string& path) {
  std::vector<TextLine> lines = dataLines(path, true);
  while (!lines.empty() && lines.back().text.empty()) lines.pop_back();  // a trailing empty line
  std::vector<ColmapImage> images;
  for (size_t k = 0; k < lines.size(); k += 2) {  // the image's line, then its 2D points' (maybe empty)
    std::istringstream in(lines[k].text);
    ColmapImage im;
    const size_t n = lines[k].number;
    im.id = field<uint32_t>(in, path, n, "an image id");
    for (int c = 0; c < 4; c++) im.q[c] = field<double>(in, path, n, "the quaternion QW QX QY QZ");
    for (int c = 0; c < 3; c++) im.t[c] = field<double>(in, path, n, "the translation TX TY TZ");
    im.cameraId = field<uint32_t>(in, path, n, "a camera id");
    std::string rest;
    std::getline(in, rest);
    size_t first = rest.find_first_not_of(" \t");
    im.name = first == std::string::npos ? "" : rest.substr(first);
    checkImage(im, path);
    if (k + 1 < lines.size() && !isPointsLine(lines[k + 1].text))
      fail(path + ": line " + std::to_string(lines[k + 1].number) + ": expected the POINTS2D line of image " + std::to_string(im.id) + " (" +
           im.name + ": X Y POINT3D_ID triples, or an empty line), found another line; each image takes two lines");
    images.push_back(im);
  }
  return images;
}

std::vector<ColmapPoint> readPointsText(const std::string& path) {
  std::vector<ColmapPoint> points;
  for (const auto& [n, line] : dataLines(path, false)) {
    std::istringstream in(line);
    ColmapPoint p;
    field<uint64_t>(in, path, n, "a point id");
    for (int c = 0; c < 3; c++) p.position[c] = field<double>(in, path, n, "the position X Y Z");
    for (int c = 0; c < 3; c++) p.colour[c] = field<int>(in, path, n, "the colour R G B") / 255.0;
    p.error = field<double>(in, path, n, "the reprojection error");
    uint64_t id;
    while (in >> id) p.views++;
    p.views /= 2;  // (image id, point2D index) pairs
    for (int c = 0; c < 3; c++)
      if (!std::isfinite(p.position[c])) fail(path + ": line " + std::to_string(n) + ": a non-finite position");
    points.push_back(p);
  }
  return points;
}

// One pose per photo and one photo per id: two entries for the same file would train two
// conflicting poses of one image, two with the same id are no model COLMAP writes.
void checkUniqueImages(const std::vector<ColmapImage>& images, const std::string& path) {
  std::map<uint32_t, const ColmapImage*> byId;
  std::map<std::string, const ColmapImage*> byName;
  for (const ColmapImage& im : images) {
    if (auto [it, fresh] = byId.emplace(im.id, &im); !fresh)
      fail(path + ": image id " + std::to_string(im.id) + " appears twice (" + it->second->name + " and " + im.name + ")");
    if (auto [it, fresh] = byName.emplace(im.name, &im); !fresh)
      fail(path + ": " + im.name + " is listed twice (images " + std::to_string(it->second->id) + " and " + std::to_string(im.id) +
           "), with two poses for one photo");
  }
}

std::string numberText(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

size_t colmapParamCount(const std::string& model) {
  int id = modelId(model);
  return id < 0 ? 0 : kModels[id].params;
}

bool hasColmapModel(const std::string& folder) { return fileExists(folder + "/cameras.bin") || fileExists(folder + "/cameras.txt"); }

ColmapModel readColmapModel(const std::string& folder) {
  auto pick = [&](const char* name) {
    std::string bin = folder + "/" + name + ".bin", txt = folder + "/" + name + ".txt";
    return fileExists(bin) ? bin : txt;
  };
  ColmapModel m;
  const std::string cameras = pick("cameras"), images = pick("images"), points = pick("points3D");
  if (!fileExists(cameras)) fail("no COLMAP model in " + folder + ": expected cameras.bin or cameras.txt");
  if (!fileExists(images)) fail("COLMAP model " + folder + ": no images.bin or images.txt beside " + cameras);
  m.cameras = cameras.size() > 4 && cameras.compare(cameras.size() - 4, 4, ".bin") == 0 ? readCamerasBinary(cameras) : readCamerasText(cameras);
  m.images = images.compare(images.size() - 4, 4, ".bin") == 0 ? readImagesBinary(images) : readImagesText(images);
  checkUniqueImages(m.images, images);
  if (fileExists(points)) m.points = points.compare(points.size() - 4, 4, ".bin") == 0 ? readPointsBinary(points) : readPointsText(points);
  for (const ColmapImage& im : m.images)
    if (!m.cameras.count(im.cameraId))
      fail(images + ": image " + std::to_string(im.id) + " (" + im.name + ") names camera " + std::to_string(im.cameraId) + ", which " +
           cameras + " does not hold");
  return m;
}

void writeColmapModel(const std::string& folder, const ColmapModel& m, bool binary) {
  if (binary) {
    Writer c, i, p;
    c.put<uint64_t>(m.cameras.size());
    for (const auto& [id, cam] : m.cameras) {
      int model = modelId(cam.model);
      if (model < 0 || cam.params.size() != kModels[model].params) fail("writeColmapModel: camera " + std::to_string(id) + " is malformed");
      c.put<uint32_t>(id);
      c.put<int32_t>(model);
      c.put<uint64_t>(cam.width);
      c.put<uint64_t>(cam.height);
      for (double v : cam.params) c.put<double>(v);
    }
    i.put<uint64_t>(m.images.size());
    for (const ColmapImage& im : m.images) {
      i.put<uint32_t>(im.id);
      for (int k = 0; k < 4; k++) i.put<double>(im.q[k]);
      for (int k = 0; k < 3; k++) i.put<double>(im.t[k]);
      i.put<uint32_t>(im.cameraId);
      i.bytes += im.name;
      i.bytes += '\0';
      i.put<uint64_t>(0);  // no 2D points
    }
    p.put<uint64_t>(m.points.size());
    for (size_t k = 0; k < m.points.size(); k++) {
      const ColmapPoint& pt = m.points[k];
      p.put<uint64_t>(k + 1);
      for (int a = 0; a < 3; a++) p.put<double>(pt.position[a]);
      for (int a = 0; a < 3; a++) p.put<uint8_t>(uint8_t(std::lround(glm::clamp(pt.colour[a], 0.0, 1.0) * 255)));
      p.put<double>(pt.error);
      p.put<uint64_t>(0);  // no track
    }
    writeFileAtomic(folder + "/cameras.bin", c.bytes.data(), c.bytes.size());
    writeFileAtomic(folder + "/images.bin", i.bytes.data(), i.bytes.size());
    writeFileAtomic(folder + "/points3D.bin", p.bytes.data(), p.bytes.size());
    return;
  }
  std::string c = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  for (const auto& [id, cam] : m.cameras) {
    c += std::to_string(id) + " " + cam.model + " " + std::to_string(cam.width) + " " + std::to_string(cam.height);
    for (double v : cam.params) c += " " + numberText(v);
    c += "\n";
  }
  std::string i = "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
                  "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  for (const ColmapImage& im : m.images) {
    i += std::to_string(im.id);
    for (int k = 0; k < 4; k++) i += " " + numberText(im.q[k]);
    for (int k = 0; k < 3; k++) i += " " + numberText(im.t[k]);
    i += " " + std::to_string(im.cameraId) + " " + im.name + "\n\n";
  }
  std::string p = "# 3D point list with one line of data per point:\n#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
  for (size_t k = 0; k < m.points.size(); k++) {
    const ColmapPoint& pt = m.points[k];
    p += std::to_string(k + 1);
    for (int a = 0; a < 3; a++) p += " " + numberText(pt.position[a]);
    for (int a = 0; a < 3; a++) p += " " + std::to_string(std::lround(glm::clamp(pt.colour[a], 0.0, 1.0) * 255));
    p += " " + numberText(pt.error) + "\n";
  }
  writeTextAtomic(folder + "/cameras.txt", c);
  writeTextAtomic(folder + "/images.txt", i);
  writeTextAtomic(folder + "/points3D.txt", p);
}

glm::dmat3 colmapRotation(const glm::dvec4& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // rows of COLMAP's qvec2rotmat, stored column-major
  glm::dmat3 r;
  r[0] = glm::dvec3(1 - 2 * y * y - 2 * z * z, 2 * x * y + 2 * w * z, 2 * x * z - 2 * w * y);
  r[1] = glm::dvec3(2 * x * y - 2 * w * z, 1 - 2 * x * x - 2 * z * z, 2 * y * z + 2 * w * x);
  r[2] = glm::dvec3(2 * x * z + 2 * w * y, 2 * y * z - 2 * w * x, 1 - 2 * x * x - 2 * y * y);
  return r;
}

glm::dvec4 colmapQuaternion(const glm::dmat3& r) {
  glm::dquat q = glm::quat_cast(r);
  glm::dvec4 out(q.w, q.x, q.y, q.z);
  return (out[0] < 0 ? -out : out) / glm::length(out);
}

}  // namespace refrax
