#include "engine/run/checkpoint_files.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/run/checkpoint_format.h"

namespace refrax {
namespace {

int stepOfName(const std::string& name) {
  if (name.rfind("step_", 0) != 0 || name.size() < 11 || name.substr(name.size() - 5) != ".ckpt") return -1;
  std::string digits = name.substr(5, name.size() - 10);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(digits);
}

}  // namespace

std::string checkpointPath(const std::string& runDir, int step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%07d.ckpt", step);
  return (std::filesystem::path(runDir) / "checkpoints" / name).string();
}

std::string latestCheckpoint(const std::string& runDir) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return "";
  int best = -1;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) best = std::max(best, stepOfName(e.path().filename().string()));
  return best < 0 ? "" : checkpointPath(runDir, best);
}

int checkpointStep(const std::string& path) { return stepOfName(std::filesystem::path(path).filename().string()); }

std::string intactCheckpointBefore(const std::string& runDir, int step) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    int k = stepOfName(e.path().filename().string());
    if (k >= 0 && k < step) steps.push_back(k);
  }
  std::sort(steps.rbegin(), steps.rend());
  for (int k : steps) {
    try {
      verifyCheckpointFile(checkpointPath(runDir, k));
      return checkpointPath(runDir, k);
    } catch (const Error&) {
    }
  }
  return "";
}

void verifyCheckpointFile(const std::string& path) { verifyCheckpointBytes(readFile(path), path); }

}  // namespace refrax
