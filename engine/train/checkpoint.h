#pragma once
// Training checkpoints: every parameter (Gaussian table, height-field weights or plane
// height), every Adam moment and step, the surface gradient summed since its last step
// (--surface-batch), the step count, the RNG and the view order, so that
// resuming continues exactly where the run stopped. RUN/checkpoints/step_NNNNNNN.ckpt,
// written atomically (temp file + rename); the two newest are kept.
//
// Format (little-endian): char[8] "RFXCKPT\0", u32 version, then length-prefixed sections
// (u64 byte count + bytes) in a fixed order, then a u32 FNV-1a checksum of every byte before
// it. A missing, truncated, corrupted or mismatched file is one refrax::Error.
#include <string>

#include "engine/run/checkpoint_files.h"
#include "engine/train/train_session.h"

namespace refrax {

void saveCheckpoint(TrainSession& session, const std::string& runDir);
// Restores a session created from the run's config.json.
void loadCheckpoint(TrainSession& session, const std::string& path);

}  // namespace refrax
