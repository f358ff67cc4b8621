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
#include "engine/run/checkpoint_format.h"
#include "engine/train/train_session.h"

namespace refrax {

// Everything a checkpoint holds, in one struct (engine/run/checkpoint_format.h): the model's
// parameters and the session's TrainingState and WaterLearning sums and moments. The water's
// pending gradient is pushed into the parameters' sum first.
CheckpointContents checkpointContents(TrainSession& session);
// Installs them into a session created from the run's config.json, which then continues as
// the saved one would. The contents come from decodeCheckpoint, which checked them against
// this session's shape (checkpointShapeFor), or from checkpointContents of a session made
// from the same config.
void restoreCheckpointContents(TrainSession& session, CheckpointContents contents);

// checkpointContents, encoded and written as RUN/checkpoints/step_NNNNNNN.ckpt.
void saveCheckpoint(TrainSession& session, const std::string& runDir);
// Decoded (every check in decodeCheckpoint) and restored into a session created from the
// run's config.json.
void loadCheckpoint(TrainSession& session, const std::string& path);

}  // namespace refrax
