#include "engine/io/ply_header.h"

#include <map>
#include <sstream>

#include "engine/base/error.h"

namespace refrax {
namespace {

size_t scalarBytes(const std::string& type) {
  static const std::map<std::string, size_t> sizes = {{"char", 1},   {"uchar", 1},  {"int8", 1},    {"uint8", 1},   {"short", 2},
                                                       {"ushort", 2}, {"int16", 2},  {"uint16", 2},  {"int", 4},     {"uint", 4},
                                                       {"int32", 4},  {"uint32", 4}, {"float", 4},   {"float32", 4}, {"double", 8},
                                                       {"float64", 8}};
  auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

}  // namespace

PlyHeader readPlyHeader(std::istream& in, const std::string& where, const std::string& holds) {
  std::string line;
  if (!std::getline(in, line) || line != "ply") fail(where + " is not a PLY file");
  bool sawFormat = false, inVertex = false, sawEnd = false;
  PlyHeader h;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      std::string fmt;
      ls >> fmt;
      if (fmt != "binary_little_endian" && fmt != "ascii") fail(where + " is '" + fmt + "', only binary_little_endian and ascii are supported");
      h.ascii = fmt == "ascii";
      sawFormat = true;
    } else if (word == "element") {
      std::string name;
      ls >> name;
      if (name == "vertex") {
        if (!(ls >> h.count)) fail(where + ": bad vertex count");
        inVertex = true;
      } else {
        long n = 0;
        ls >> n;
        if (n != 0) fail(where + ": unsupported element '" + name + "' (only 'vertex' is read)");
        inVertex = false;
      }
    } else if (word == "property") {
      std::string type, name;
      ls >> type;
      if (type == "list") fail(where + ": list properties are not supported");
      ls >> name;
      if (!inVertex) continue;
      size_t bytes = scalarBytes(type);
      if (bytes == 0) fail(where + ": unknown property type '" + type + "'");
      h.props.push_back({name, type, bytes});
    } else if (word == "end_header") {
      sawEnd = true;
      break;
    }
  }
  if (!sawEnd) fail(where + ": header has no end_header");
  if (!sawFormat) fail(where + ": header has no format line");
  if (h.count == 0) fail(where + " holds no " + holds);
  return h;
}


}  // namespace refrax
