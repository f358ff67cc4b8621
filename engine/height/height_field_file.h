#pragma once
// The height field's file format (engine/height/height_field.h saveHeightField / loadHeightField),
// apart from any device, so it can be read (and fuzzed: fuzz/) without Vulkan:
//   char[8] "RFXHGTF\0", u32 version (2), u32 octaves, width, hiddenLayers,
//   f32 leakySlope, lastLayerInitRange, initialHeight, domainMin[2], domainMax[2], encodingWindow
//   (version 2), u64 parameterCount, f32 weights[parameterCount], u32 FNV-1a checksum of every
//   byte before it (little-endian).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/height/height_field.h"

namespace refrax {

struct HeightFieldFile {
  HeightFieldConfig config;
  std::vector<float> weights;
};

std::vector<uint8_t> encodeHeightFieldFile(const HeightFieldConfig& config, const std::vector<float>& weights);
// refrax::Error naming `path` on a bad magic, version, configuration, size or checksum.
HeightFieldFile decodeHeightFieldFile(const std::vector<uint8_t>& bytes, const std::string& path);

}  // namespace refrax
