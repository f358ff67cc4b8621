#pragma once
// A run's checkpoint files: RUN/checkpoints/step_NNNNNNN.ckpt (engine/train/checkpoint.h
// writes them), found and checked without a session or a device.
#include <string>

namespace refrax {

std::string checkpointPath(const std::string& runDir, int step);
// The newest checkpoint of the run ("" when there is none).
std::string latestCheckpoint(const std::string& runDir);
// Checks the file's magic, version and checksum (refrax::Error otherwise).
void verifyCheckpointFile(const std::string& path);
// The step of a checkpoint from its file name (-1 when it is not one).
int checkpointStep(const std::string& path);
// The newest checkpoint of the run before `step` that verifies ("" when none does): what a
// run whose newest checkpoint is corrupted can resume from.
std::string intactCheckpointBefore(const std::string& runDir, int step);

}  // namespace refrax
