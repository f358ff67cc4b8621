// Height field files on disk (format: engine/height/height_field_file.h), written to a temporary
// file and renamed so a reader never sees half a file.
#include <cstdio>
#include <fstream>
#include <iterator>

#include "engine/base/error.h"
#include "engine/height/height_field.h"
#include "engine/height/height_field_file.h"

namespace refrax {

void saveHeightField(const std::string& path, Context& ctx, const HeightField& hf) {
  const std::vector<uint8_t> bytes = encodeHeightFieldFile(hf.config, downloadWeights(ctx, hf));
  std::string temp = path + ".tmp";
  {
    std::ofstream f(temp, std::ios::binary | std::ios::trunc);
    if (!f) fail("cannot write height field file '" + temp + "'");
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    f.flush();
    if (!f) {
      std::remove(temp.c_str());
      fail("cannot write height field file '" + temp + "' (disk full?)");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    fail("cannot move '" + temp + "' to '" + path + "'");
  }
}

HeightField loadHeightField(Context& ctx, const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) fail("cannot open height field file '" + path + "'");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  HeightFieldFile file = decodeHeightFieldFile(bytes, path);
  HeightField hf = createHeightField(ctx, file.config, 0);
  uploadWeights(ctx, hf, file.weights);
  return hf;
}

}  // namespace refrax
