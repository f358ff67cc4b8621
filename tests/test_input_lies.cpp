// Inputs that lied, second round (issue 51: a hostile but realistic user's 124 tries): two
// trainings given one folder, COLMAP files with duplicate or missing lines, a render that
// failed half-way, an evaluation against another scene, and messages that named the wrong
// thing. Each case below once passed silently or said the wrong words.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/io/staged_folder.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace fs = std::filesystem;
using namespace refrax;
using test::TrainTempDir;

namespace {

size_t lineCount(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

using test::checkOneError;

// The folders in `dir` whose names start with `stem` (the output and any staged sibling).
std::vector<std::string> foldersStartingWith(const fs::path& dir, const std::string& stem) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && e.path().filename().string().rfind(stem, 0) == 0) names.push_back(e.path().filename().string());
  return names;
}

// A shell command line run through sh (for a background process and a signal); its output.
std::string shell(const std::string& script) {
  std::string out;
  FILE* p = popen(("sh -c '" + script + "' 2>&1").c_str(), "r");
  REQUIRE(p);
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

std::string refraxBinary() {
  const char* cli = std::getenv("REFRAX_CLI");
  return cli ? cli : REFRAX_CLI;
}

// COLMAP's text header for images.txt (four comment lines), then `body`.
void writeColmapText(const fs::path& dir, const std::string& images) {
  fs::create_directories(dir);
  writeTextAtomic((dir / "cameras.txt").string(), "# Camera list\n# CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n1 PINHOLE 64 48 50 50 32 24\n");
  writeTextAtomic((dir / "images.txt").string(), "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
                                                  "#   POINTS2D[] as (X, Y, POINT3D_ID)\n# Number of images: 3\n" + images);
}

std::string imageLine(int id, const std::string& name, double tx = 0) {
  return std::to_string(id) + " 1 0 0 0 " + std::to_string(tx) + " 0 1 1 " + name + "\n";
}

}  // namespace

TEST_CASE("two trainings given one folder at the same moment: exactly one claims it, the other names it" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string run = dir / "run";
  test::CliResult a, b;
  std::thread first([&] { a = test::runCli("train " + data + " -o " + run + " --steps 20 --gaussians 200 --patch 16 --seed 1 --checkpoint-every 10"); });
  std::thread second([&] { b = test::runCli("train " + data + " -o " + run + " --steps 20 --gaussians 300 --patch 16 --seed 7 --checkpoint-every 10"); });
  first.join();
  second.join();
  INFO("first: " << a.output);
  INFO("second: " << b.output);
  REQUIRE((a.exitCode == 0) != (b.exitCode == 0));  // one, not both, not neither
  const test::CliResult& loser = a.exitCode == 0 ? b : a;
  const int winnerSeed = a.exitCode == 0 ? 1 : 7;
  const unsigned winnerGaussians = a.exitCode == 0 ? 200 : 300;
  CHECK(lineCount(loser.output) == 1);
  // Refused while the other trains, or (had it finished first) as a folder already written.
  CHECK(loser.output.find(run) != std::string::npos);
  CHECK((loser.output.find("is being written by another refrax process") != std::string::npos ||
         loser.output.find("already exists and is not empty") != std::string::npos));
  // The winner's outputs, untouched: its configuration beside its own checkpoints.
  const nlohmann::json config = readJson(run + "/config.json");
  CHECK(config["seed"] == winnerSeed);
  CHECK(config["initial_gaussians"] == winnerGaussians);
  CHECK(readJson(run + "/metrics.json")["step"] == 20);
  CHECK(test::runCli("train --resume " + run + " --steps 22").exitCode == 0);  // its checkpoint matches its configuration
}

TEST_CASE("a run folder held by another refrax process is refused to a new training and to --resume" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string run = dir / "run";
  fs::create_directories(run);
  {
    // This process plays the other refrax: it holds the lock a training holds.
    int fd = ::open(run.c_str(), O_RDONLY | O_DIRECTORY);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    checkOneError(test::runCli("train " + data + " -o " + run + " --steps 2 --gaussians 100 --patch 16"),
                  "-o " + run + " is being written by another refrax process");
    CHECK(fs::is_directory(run));  // left to its owner, though empty
    ::close(fd);
  }
  REQUIRE(test::runCli("train " + data + " -o " + run + " --steps 2 --gaussians 100 --patch 16 --checkpoint-every 1").exitCode == 0);
  int fd = ::open(run.c_str(), O_RDONLY | O_DIRECTORY);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
  checkOneError(test::runCli("train --resume " + run + " --steps 4"), run + " is being written by another refrax process");
  ::close(fd);
  CHECK(readJson(run + "/metrics.json")["step"] == 2);
}

TEST_CASE("COLMAP images.txt: the same photo or the same id twice is refused, naming both entries" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const fs::path model = fs::path(dir.path) / "sparse/0";
  writeColmapText(model, imageLine(1, "a.png") + "\n" + imageLine(2, "b.png", 0.1) + "\n" + imageLine(3, "a.png", 0.2) + "\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("a.png is listed twice (images 1 and 3)"), Error);
  checkOneError(test::runCli("inspect " + dir.path.string()), "a.png is listed twice (images 1 and 3), with two poses for one photo");

  writeColmapText(model, imageLine(1, "a.png") + "\n" + imageLine(2, "b.png", 0.1) + "\n" + imageLine(2, "c.png", 0.2) + "\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("image id 2 appears twice (b.png and c.png)"), Error);

  // The binary files are held to the same (written by the project's own writer).
  ColmapModel m;
  m.cameras[1] = {1, "PINHOLE", 64, 48, {50, 50, 32, 24}};
  m.images = {{1, {1, 0, 0, 0}, {0, 0, 1}, 1, "a.png"}, {2, {1, 0, 0, 0}, {0.1, 0, 1}, 1, "a.png"}};
  fs::remove_all(model);
  fs::create_directories(model);
  writeColmapModel(model.string(), m, true);
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("images.bin: a.png is listed twice"), Error);
  m.images[1].name = "b.png";
  m.images[1].id = 1;
  writeColmapModel(model.string(), m, true);
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("images.bin: image id 1 appears twice"), Error);
  m.images[1].id = 2;
  writeColmapModel(model.string(), m, true);
  CHECK(readColmapModel(model.string()).images.size() == 2);
}

TEST_CASE("COLMAP images.txt without its POINTS2D lines is refused at the file's line, not read as half the images" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const fs::path model = fs::path(dir.path) / "sparse/0";
  std::string body;
  for (int i = 1; i <= 9; i++) body += imageLine(i, "view_" + std::to_string(i) + ".png", 0.1 * i);  // no POINTS2D lines
  writeColmapText(model, body);
  // The header's four comment lines come first: image 1 is on line 5, image 2 on line 6.
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("images.txt: line 6: expected the POINTS2D line of image 1 (view_1.png"), Error);
  checkOneError(test::runCli("inspect " + dir.path.string()), "line 6: expected the POINTS2D line of image 1");

  // POINTS2D lines of triples, an empty one, and the last image's left off at the end all load.
  writeColmapText(model, imageLine(1, "a.png") + "10.5 20 -1 30 40.25 7\n" + imageLine(2, "b.png", 0.1) + "\n" + imageLine(3, "c.png", 0.2));
  CHECK(readColmapModel(model.string()).images.size() == 3);
  // a points line that is not triples of numbers
  writeColmapText(model, imageLine(1, "a.png") + "10.5 20\n" + imageLine(2, "b.png", 0.1) + "\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("images.txt: line 6: expected the POINTS2D line of image 1"), Error);
}

TEST_CASE("COLMAP text errors name the file's line, comments counted" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const fs::path model = fs::path(dir.path) / "sparse/0";
  writeColmapText(model, imageLine(1, "a.png") + "\n" + imageLine(2, "b.png", 0.1) + "\n");
  // cameras.txt: two comment lines, a camera, a comment, then a NaN on line 5
  writeTextAtomic((model / "cameras.txt").string(), "# Camera list\n# CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n1 PINHOLE 64 48 50 50 32 24\n# another\n"
                                                     "2 PINHOLE 64 48 nan 50 32 24\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("cameras.txt: line 5: a camera parameter is not a number"), Error);
  writeTextAtomic((model / "cameras.txt").string(), "# Camera list\n1 PINHOLE 64 48 50 50 32 24\n");
  // images.txt: the second image's quaternion is cut short on file line 7
  writeColmapText(model, imageLine(1, "a.png") + "\n" + "2 1 0 0\n\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("images.txt: line 7: expected the quaternion"), Error);
  // points3D.txt: a comment, a point, then a bad colour on line 3
  writeColmapText(model, imageLine(1, "a.png") + "\n" + imageLine(2, "b.png", 0.1) + "\n");
  writeTextAtomic((model / "points3D.txt").string(), "# 3D point list\n1 0 0 -1 128 128 128 0.5 1 0\n2 0 0 -1 red 128 128 0.5 1 0\n");
  CHECK_THROWS_WITH_AS(readColmapModel(model.string()), doctest::Contains("points3D.txt: line 3: expected the colour"), Error);
}

TEST_CASE("a staged folder appears whole or not at all" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string out = dir / "out";
  {  // an error before commit: nothing is left, neither the target nor the staging
    StagedFolder f(out, "-o");
    writeTextAtomic(f.path + "/a.txt", "a");
  }
  CHECK(!fs::exists(out));
  CHECK(foldersStartingWith(dir.path, "out").empty());
  {  // committed onto an empty folder the user made
    fs::create_directories(out);
    StagedFolder f(out, "-o");
    writeTextAtomic(f.path + "/a.txt", "a");
    f.commit();
  }
  CHECK(readFile(out + "/a.txt") == "a");
  CHECK(foldersStartingWith(dir.path, "out") == std::vector<std::string>{"out"});
  {  // a target that gained files meanwhile is not replaced, and the staging goes
    StagedFolder f(out, "-o");
    writeTextAtomic(f.path + "/b.txt", "b");
    const std::string words = "cannot move the finished outputs into " + out;
    CHECK_THROWS_WITH_AS(f.commit(), doctest::Contains(words.c_str()), Error);
  }
  CHECK(!fs::exists(out + "/b.txt"));
  CHECK(foldersStartingWith(dir.path, "out") == std::vector<std::string>{"out"});
}

TEST_CASE("a render stopped half-way leaves no folder behind, and the same command then works" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string run = dir / "run";
  REQUIRE(test::runCli("train " + data + " -o " + run + " --steps 2 --gaussians 100 --patch 16").exitCode == 0);
  const std::string out = dir / "ren";
  // Killed (SIGTERM) as soon as its folder appears: before the fix it left ren/ with the
  // images written so far, and the same command was then refused as "not empty".
  const std::string log = shell(refraxBinary() + " render " + run + " -o " + out + " --split train > " + (dir / "log.txt") + " 2>&1 & pid=$!; " +
                                "for i in $(seq 3000); do ls -d " + out + "* >/dev/null 2>&1 && break; sleep 0.01; done; " +
                                "kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(log);
  INFO(readFile(dir / "log.txt"));
  CHECK(log.find("exit=0") == std::string::npos);
  CHECK(readFile(dir / "log.txt").find("render: interrupted; nothing was written to " + out) != std::string::npos);
  CHECK(foldersStartingWith(dir.path, "ren").empty());
  test::CliResult again = test::runCli("render " + run + " -o " + out + " --split train");
  INFO(again.output);
  REQUIRE(again.exitCode == 0);
  CHECK(fs::exists(out + "/train_007.png"));
  CHECK(foldersStartingWith(dir.path, "ren") == std::vector<std::string>{"ren"});
}

TEST_CASE("an evaluation dataset of another scene is refused, or evaluated with --force and a warning" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string run = dir / "run";
  REQUIRE(test::runCli("train " + data + " -o " + run + " --steps 2 --gaussians 100 --patch 16").exitCode == 0);
  const std::string desk = test::tinyDataset("desk");
  test::CliResult r = test::runCli("eval " + run + " --dataset " + desk + " -o " + (dir / "m.json"));
  checkOneError(r, "--dataset " + desk + " is not the scene " + run + " learned: its IOR is 1.33, the run's 1.1");
  CHECK(r.output.find("its water domain is x -1.5..1.5") != std::string::npos);
  CHECK(r.output.find("--force") != std::string::npos);
  CHECK(!fs::exists(dir / "m.json"));
  // The same cameras under other water: the IOR alone tells.
  r = test::runCli("eval " + run + " --dataset " + test::tinyDataset("nerfrac-primary-sine", "--ior 1.5") + " -o " + (dir / "m.json"));
  checkOneError(r, "its IOR is 1.5, the run's 1.1");
  // The same water seen from another rig: the cameras tell.
  r = test::runCli("eval " + run + " --dataset " + test::tinyDataset("nerfrac-primary-sine", "--rig-spacing 0.3") + " -o " + (dir / "m.json"));
  checkOneError(r, "its training view 0");

  r = test::runCli("eval " + run + " --dataset " + desk + " --force -o " + (dir / "m.json"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(r.output.find("warning: --dataset " + desk + " is not the scene " + run + " learned") != std::string::npos);
  const nlohmann::json m = readJson(dir / "m.json");
  REQUIRE(m.contains("dataset_mismatches"));
  CHECK(m["dataset_mismatches"].size() == 3);  // IOR, domain, the number of training views

  // The run's own scene, its dry copy and the same views at another size are no other scene.
  for (const std::string& same : {data, test::tinyDataset("nerfrac-primary-sine", "--dry"), test::tinyDataset("nerfrac-primary-sine", "--width 48")}) {
    r = test::runCli("eval " + run + " --dataset " + same + " -o " + (dir / "same.json"));
    INFO(same << ": " << r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("warning") == std::string::npos);
    CHECK(!readJson(dir / "same.json").contains("dataset_mismatches"));
  }
}

TEST_CASE("messages that named the wrong thing now say what is wrong" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  checkOneError(test::runCli("train " + data + " -o " + (dir / "r") + " --time-limit 1e9"),
                "--time-limit must be a number of seconds above 0 and below 1e9");
  checkOneError(test::runCli("train " + data + " -o " + (dir / "r") + " --time-limit 0"), "got 0");
  const std::string file = dir / "a-file";
  writeTextAtomic(file, "x");
  checkOneError(test::runCli("train " + data + " -o " + file), "-o " + file + " is a file, not a folder");
  checkOneError(test::runCli("render " + file + " -o " + file), "-o " + file + " is a file, not a folder");
  CHECK(readFile(file) == "x");
  CHECK(!fs::exists(dir / "r"));
}
