#pragma once
// The checkpoint file's bytes (engine/train/checkpoint.h), apart from any session or device:
// what a checkpoint holds, its encoding, and its decoding with every check, so the format can
// be read (and fuzzed: fuzz/) without a Vulkan device.
//
// Format (little-endian): char[8] "RFXCKPT\0", u32 version, then length-prefixed sections
// (u64 byte count + bytes) in a fixed order, then a u32 FNV-1a checksum of every byte before it.
#include <cstdint>
#include <string>
#include <vector>

namespace refrax {

struct CheckpointContents {
  std::string model;  // waterModelName
  int32_t step = 0;
  double trainingSeconds = 0;
  std::string rng;  // std::mt19937 as text
  std::vector<uint32_t> viewOrder;
  uint32_t viewCursor = 0;
  uint64_t gaussians = 0;
  std::vector<float> params, adamM, adamV;  // gaussians * kGaussianFloats each
  std::vector<int32_t> groupSteps;          // one per Gaussian Adam group
  std::vector<float> densifyStats;          // gaussians * 2
  uint64_t heightCount = 0;                 // height-field weights (0: no MLP)
  std::vector<float> heightWeights, heightM, heightV, heightGrad;
  int32_t heightStep = 0;
  double planeHeight = 0, planeM = 0, planeV = 0, planeGrad = 0;
  int32_t planeStep = 0;
};

// What the session that will load a checkpoint expects of it.
struct CheckpointShape {
  std::string model;
  size_t trainViews = 0;
  size_t adamGroups = 0;
  uint64_t heightCount = 0;
};

uint32_t checkpointChecksum(const char* data, size_t n);  // FNV-1a
std::string encodeCheckpoint(const CheckpointContents& c);
// The magic and checksum only (refrax::Error naming `path` otherwise).
void verifyCheckpointBytes(const std::string& bytes, const std::string& path);
// Every section, checked against `shape` (refrax::Error naming `path` on any mismatch).
CheckpointContents decodeCheckpoint(const std::string& bytes, const std::string& path, const CheckpointShape& shape);

}  // namespace refrax
