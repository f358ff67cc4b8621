#include "engine/io/npy.h"

#include <cstdint>
#include <cstring>
#include <regex>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

size_t NpyArray::size() const {
  size_t n = 1;
  for (size_t s : shape) n *= s;
  return n;
}

NpyArray parseNpy(const std::string& bytes, const std::string& name) {
  auto bad = [&](const std::string& why) { fail(name + " is not a valid .npy file: " + why); };
  if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0) bad("missing the \\x93NUMPY magic");
  uint8_t major = uint8_t(bytes[6]);
  size_t headerLen, offset;
  if (major == 1) {
    headerLen = uint8_t(bytes[8]) | (size_t(uint8_t(bytes[9])) << 8);
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) bad("truncated header");
    headerLen = 0;
    for (int i = 0; i < 4; i++) headerLen |= size_t(uint8_t(bytes[8 + i])) << (8 * i);
    offset = 12;
  } else {
    bad("unsupported format version " + std::to_string(major));
  }
  if (offset + headerLen > bytes.size()) bad("truncated header");
  std::string header = bytes.substr(offset, headerLen);
  std::smatch m;
  if (!std::regex_search(header, m, std::regex("'descr'\\s*:\\s*'([^']*)'"))) bad("no 'descr' in the header");
  std::string descr = m[1];
  if (std::regex_search(header, m, std::regex("'fortran_order'\\s*:\\s*True"))) bad("Fortran order is not supported");
  if (!std::regex_search(header, m, std::regex("'shape'\\s*:\\s*\\(([^)]*)\\)"))) bad("no 'shape' in the header");
  NpyArray a;
  std::string dims = m[1];
  std::regex num("(\\d+)");
  for (auto it = std::sregex_iterator(dims.begin(), dims.end(), num); it != std::sregex_iterator(); ++it) {
    const std::string digits = (*it)[1];
    if (digits.size() > 12) bad("a dimension of the shape (" + digits.substr(0, 20) + ") is too large");
    a.shape.push_back(std::stoull(digits));
  }
  size_t elements = 1;
  for (size_t d : a.shape) {
    if (d != 0 && elements > (uint64_t(1) << 40) / d) bad("the shape holds more than 2^40 values");
    elements *= d;
  }
  size_t width;
  if (descr == "<f4" || descr == "<i4") width = 4;
  else if (descr == "<f8" || descr == "<i8") width = 8;
  else bad("dtype '" + descr + "' is not supported (little-endian float32/float64/int32/int64 only)");
  size_t n = a.size(), start = offset + headerLen;
  if (bytes.size() - start != n * width)
    bad("data holds " + std::to_string(bytes.size() - start) + " bytes, the shape needs " + std::to_string(n * width));
  a.data.resize(n);
  a.integer = descr[1] == 'i';
  const char* p = bytes.data() + start;
  for (size_t i = 0; i < n; i++, p += width) {
    if (descr == "<f4") { float v; std::memcpy(&v, p, 4); a.data[i] = v; }
    else if (descr == "<f8") { std::memcpy(&a.data[i], p, 8); }
    else if (descr == "<i4") { int32_t v; std::memcpy(&v, p, 4); a.data[i] = v; }
    else { int64_t v; std::memcpy(&v, p, 8); a.data[i] = double(v); }
  }
  return a;
}

NpyArray readNpy(const std::string& path) { return parseNpy(readFile(path), path); }

void writeNpy(const std::string& path, const NpyArray& array, bool float64) {
  if (array.data.size() != array.size()) fail("writeNpy: data does not match the shape for " + path);
  std::string shape = "(";
  for (size_t i = 0; i < array.shape.size(); i++) shape += std::to_string(array.shape[i]) + (array.shape.size() == 1 ? "," : i + 1 < array.shape.size() ? ", " : "");
  shape += ")";
  std::string header = std::string("{'descr': '") + (float64 ? "<f8" : "<f4") + "', 'fortran_order': False, 'shape': " + shape + ", }";
  // pad so that the data starts at a multiple of 64 bytes, header ends with '\n'
  size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += char(header.size() & 0xFF);
  out += char((header.size() >> 8) & 0xFF);
  out += header;
  for (double v : array.data) {
    if (float64) out.append(reinterpret_cast<const char*>(&v), 8);
    else { float f = float(v); out.append(reinterpret_cast<const char*>(&f), 4); }
  }
  writeFileAtomic(path, out.data(), out.size());
}

}  // namespace refrax
