#pragma once
// Following a training run from outside (the viewer): which checkpoint was taken last, and
// whether the run now has a newer one. Checkpoints are written atomically (temp file +
// rename), so a checkpoint file that exists is complete; "newer" is another newest file, or
// the same file with a later modification time (a run restarted into the same folder).
#include <filesystem>
#include <string>

namespace refrax {

struct CheckpointWatch {
  std::string runDir;
  std::string taken;  // the checkpoint last loaded ("" before the first)
  std::filesystem::file_time_type takenTime{};
};

// The run's newest checkpoint when it differs from, or is newer than, the one taken; "" otherwise.
std::string newerCheckpoint(const CheckpointWatch& watch);
// Records `path` (with its current modification time) as loaded.
void markTaken(CheckpointWatch& watch, const std::string& path);

}  // namespace refrax
