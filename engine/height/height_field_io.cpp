// Height field files on disk (format: engine/height/height_field_file.h), written through
// writeFileAtomic (a temporary file, synced, renamed) so a reader never sees half a file.
#include <fstream>
#include <iterator>

#include "engine/base/error.h"
#include "engine/height/height_field.h"
#include "engine/height/height_field_file.h"
#include "engine/io/atomic_file.h"

namespace refrax {

void saveHeightField(const std::string& path, Context& ctx, const HeightField& hf) {
  const std::vector<uint8_t> bytes = encodeHeightFieldFile(hf.config, downloadWeights(ctx, hf));
  writeFileAtomic(path, bytes.data(), bytes.size());  // fsync'd before the rename, as every output
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
