#include "engine/train/checkpoint_watch.h"

#include "engine/run/checkpoint_files.h"

namespace refrax {

namespace {
std::filesystem::file_time_type modificationTime(const std::string& path) {
  std::error_code ec;
  auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::filesystem::file_time_type{} : t;
}
}  // namespace

std::string newerCheckpoint(const CheckpointWatch& w) {
  std::string newest = latestCheckpoint(w.runDir);
  if (newest.empty()) return "";
  if (newest != w.taken || modificationTime(newest) > w.takenTime) return newest;
  return "";
}

void markTaken(CheckpointWatch& w, const std::string& path) {
  w.taken = path;
  w.takenTime = modificationTime(path);
}

}  // namespace refrax
