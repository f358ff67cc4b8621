// Following a run's checkpoints (the viewer): a newer file, or the same file rewritten, is
// reported once; nothing new is nothing.
#include <doctest/doctest.h>

#include <chrono>
#include <fstream>

#include "engine/train/checkpoint.h"
#include "engine/train/checkpoint_watch.h"
#include "tests/train_test_util.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {
void touch(const std::string& path) { std::ofstream(path) << "x"; }
}  // namespace

TEST_CASE("a checkpoint watch reports each newer checkpoint of a run once") {
  test::TrainTempDir dir;
  std::string run = dir / "run";
  CheckpointWatch w;
  w.runDir = run;
  CHECK(newerCheckpoint(w).empty());  // no checkpoints folder yet
  fs::create_directories(run + "/checkpoints");
  CHECK(newerCheckpoint(w).empty());

  std::string c10 = checkpointPath(run, 10), c20 = checkpointPath(run, 20);
  touch(c10);
  CHECK(newerCheckpoint(w) == c10);
  markTaken(w, c10);
  CHECK(newerCheckpoint(w).empty());

  touch(c20);
  CHECK(newerCheckpoint(w) == c20);
  markTaken(w, c20);
  CHECK(newerCheckpoint(w).empty());
  fs::remove(c10);  // the trainer keeps the two newest: removing an older one is no news
  CHECK(newerCheckpoint(w).empty());

  // the same name written again later (a run restarted into the folder)
  fs::last_write_time(c20, fs::last_write_time(c20) + std::chrono::seconds(5));
  CHECK(newerCheckpoint(w) == c20);
  markTaken(w, c20);
  CHECK(newerCheckpoint(w).empty());
}
