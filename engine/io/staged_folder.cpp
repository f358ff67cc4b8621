#include "engine/io/staged_folder.h"

#include <filesystem>
#include <unistd.h>

#include "engine/base/error.h"

namespace fs = std::filesystem;

namespace refrax {

StagedFolder::StagedFolder(const std::string& targetPath, const std::string& flag) : target(targetPath) {
  fs::path t = fs::absolute(targetPath).lexically_normal();
  if (t.filename().empty()) t = t.parent_path();  // "out/"
  path = t.string() + ".tmp-" + std::to_string(getpid());
  std::error_code ec;
  fs::remove_all(path, ec);  // left by an earlier process of the same id that was killed
  fs::create_directories(t.parent_path(), ec);
  if (!fs::create_directory(path, ec) || ec)
    fail(flag + " " + targetPath + ": cannot create the folder" + (ec ? " (" + ec.message() + ")" : ""));
}

StagedFolder::~StagedFolder() {
  std::error_code ec;
  if (!committed) fs::remove_all(path, ec);
}

void StagedFolder::commit() {
  std::error_code ec;
  fs::rename(path, target, ec);  // replaces an empty folder; refuses one that holds files
  if (ec) fail("cannot move the finished outputs into " + target + " (" + ec.message() + "); nothing was written there");
  committed = true;
}

}  // namespace refrax
