#pragma once
// A PLY file's header as the readers here need it: the format and the vertex element (its
// count and scalar properties in file order). Elements other than the vertex must be empty
// (count 0) before it; what follows it is not read. List properties are refused.
#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace refrax {

struct PlyProperty {
  std::string name, type;  // type as PLY spells it: "float", "uchar", "float64", ...
  size_t bytes = 0;
  bool isFloat() const { return type == "float" || type == "float32"; }
};
struct PlyHeader {
  bool ascii = false;  // else binary_little_endian
  size_t count = 0;
  std::vector<PlyProperty> props;
};

// Reads up to end_header. refrax::Error naming `where` on anything malformed, on a big-endian
// body, and (`holds` naming what the vertices are, "Gaussians") on no vertices.
PlyHeader readPlyHeader(std::istream& in, const std::string& where, const std::string& holds);

}  // namespace refrax
