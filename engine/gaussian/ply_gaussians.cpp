#include "engine/gaussian/ply_gaussians.h"

#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/io/atomic_file.h"
#include "engine/io/ply_header.h"

namespace refrax {

namespace {

using namespace f32;  // layout offsets

// Where each PLY float goes in the parameter layout, by property name.
std::map<std::string, uint32_t> propertySlots(uint32_t restPerChannel) {
  std::map<std::string, uint32_t> slots;
  const char* xyz[3] = {"x", "y", "z"};
  for (uint32_t a = 0; a < 3; a++) slots[xyz[a]] = kGaussMean + a;
  for (uint32_t c = 0; c < 3; c++) slots["f_dc_" + std::to_string(c)] = kGaussSH + c;
  for (uint32_t c = 0; c < 3; c++)
    for (uint32_t j = 0; j < restPerChannel; j++) slots["f_rest_" + std::to_string(c * restPerChannel + j)] = kGaussSH + 3 * (j + 1) + c;
  slots["opacity"] = kGaussLogitDensity;
  for (uint32_t a = 0; a < 3; a++) slots["scale_" + std::to_string(a)] = kGaussLogScale + a;
  for (uint32_t a = 0; a < 4; a++) slots["rot_" + std::to_string(a)] = kGaussRotation + a;
  return slots;
}

}  // namespace

GaussianSet readGaussiansPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open Gaussian PLY '" + path + "'");
  const std::string where = "Gaussian PLY '" + path + "'";
  const PlyHeader header = readPlyHeader(in, where, "Gaussians");
  if (header.ascii) fail(where + " is 'ascii', only binary_little_endian is supported");
  const std::vector<PlyProperty>& props = header.props;
  const size_t count = header.count;

  size_t restCount = 0;
  for (auto& p : props) restCount += p.name.rfind("f_rest_", 0) == 0;
  if (restCount != 0 && restCount != 9 && restCount != 24 && restCount != 45)
    fail(where + ": " + std::to_string(restCount) + " f_rest properties (expected 0, 9, 24 or 45)");
  auto slots = propertySlots(uint32_t(restCount / 3));
  std::vector<int> slotOf(props.size(), -1);
  std::vector<size_t> offsetOf(props.size());
  size_t stride = 0;
  for (size_t i = 0; i < props.size(); i++) {
    offsetOf[i] = stride;
    stride += props[i].bytes;
    auto it = slots.find(props[i].name);
    if (it == slots.end()) continue;
    if (!props[i].isFloat()) fail(where + ": property '" + props[i].name + "' must be float");
    if (slotOf[i] != -1) fail(where + ": duplicate property '" + props[i].name + "'");
    slotOf[i] = int(it->second);
    slots.erase(it);
  }
  if (!slots.empty()) fail(where + " lacks the property '" + slots.begin()->first + "'");

  // The body must hold exactly the header's vertices: fewer is a truncated file, more is data
  // the header does not describe (a count edited by hand, or two files joined).
  const std::streamoff bodyStart = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t body = uint64_t(in.tellg() - bodyStart);
  in.seekg(bodyStart);
  if (stride == 0) fail(where + ": the vertex element has no properties");
  if (count > body / stride)
    fail(where + " is truncated: " + std::to_string(body / stride) + " of " + std::to_string(count) + " Gaussians present");
  if (body > uint64_t(count) * stride)
    fail(where + " holds " + std::to_string(body - uint64_t(count) * stride) + " bytes after the " + std::to_string(count) +
         " Gaussians its header gives (" + std::to_string(body / stride) + " would fit): the vertex count is wrong or data was appended");
  std::vector<char> data(count * stride);
  in.read(data.data(), std::streamsize(data.size()));
  if (size_t(in.gcount()) != data.size())
    fail(where + " is truncated: " + std::to_string(in.gcount() / stride) + " of " + std::to_string(count) + " Gaussians present");

  GaussianSet set;
  set.params.assign(count * kGaussianFloats, 0.0f);
  for (size_t g = 0; g < count; g++) {
    const char* rec = data.data() + g * stride;
    float* dst = set.at(g);
    for (size_t i = 0; i < props.size(); i++)
      if (slotOf[i] >= 0) std::memcpy(dst + slotOf[i], rec + offsetOf[i], 4);
  }
  validateGaussians(set, where.c_str());
  return set;
}

void writeGaussiansPly(const std::string& path, const GaussianSet& set) {
  validateGaussians(set, "Gaussians to write");
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  for (int i = 0; i < 45; i++) names.push_back("f_rest_" + std::to_string(i));
  names.push_back("opacity");
  for (int i = 0; i < 3; i++) names.push_back("scale_" + std::to_string(i));
  for (int i = 0; i < 4; i++) names.push_back("rot_" + std::to_string(i));
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(set.count()) + "\n";
  for (auto& n : names) header += "property float " + n + "\n";
  header += "end_header\n";

  auto slots = propertySlots(15);
  std::vector<float> rows(set.count() * names.size(), 0.0f);
  for (size_t g = 0; g < set.count(); g++)
    for (size_t i = 0; i < names.size(); i++) {
      auto it = slots.find(names[i]);
      if (it != slots.end()) rows[g * names.size() + i] = set.at(g)[it->second];  // normals stay zero
    }

  std::string bytes = header;
  bytes.append(reinterpret_cast<const char*>(rows.data()), rows.size() * sizeof(float));
  writeFileAtomic(path, bytes.data(), bytes.size());
}

}  // namespace refrax
