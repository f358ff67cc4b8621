#pragma once
// A folder of outputs that appears whole or not at all. Its files are written into a temporary
// sibling (`<target>.tmp-<pid>`); commit() renames that onto the target, which must be absent
// or an empty folder (rename replaces an empty one). A staged folder never committed (an
// error, a full disk, an interrupt between files) is removed with whatever it holds, so a
// failed command leaves the target as it found it, and the same command can run again.
#include <string>

namespace refrax {

struct StagedFolder {
  std::string target;  // where the outputs end up
  std::string path;    // where they are written until commit()
  bool committed = false;
  // Makes the temporary folder; refrax::Error naming `flag target` when it cannot be made.
  StagedFolder(const std::string& target, const std::string& flag);
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;
  ~StagedFolder();
  // Moves the finished folder into place; refrax::Error (and the temporary folder removed)
  // when the target has meanwhile gained files or the rename fails.
  void commit();
};

}  // namespace refrax
