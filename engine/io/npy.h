#pragma once
// NumPy .npy arrays (format 1.0/2.0/3.0), little-endian float32/float64 (and int32/int64 on
// read), C order. Values are held as doubles; the dtype written is chosen by the caller.
#include <cstddef>
#include <string>
#include <vector>

namespace refrax {

struct NpyArray {
  std::vector<size_t> shape;
  std::vector<double> data;  // row-major (C order)
  bool integer = false;      // the file held integers (<i4, <i8), converted
  size_t size() const;
};

NpyArray readNpy(const std::string& path);  // clear refrax::Error on malformed headers, dtypes or sizes
NpyArray parseNpy(const std::string& bytes, const std::string& nameForErrors);
void writeNpy(const std::string& path, const NpyArray& array, bool float64 = false);  // atomic

}  // namespace refrax
