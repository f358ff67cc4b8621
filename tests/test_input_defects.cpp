// Inputs that lied and runs that diverged (found by trying 245 malformed or extreme inputs as a
// new user would): each case below once passed silently or failed with the wrong words.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/dataset/dataset.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/train/checkpoint.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace fs = std::filesystem;
using namespace refrax;
using test::TrainTempDir;

using test::checkOneError;

TEST_CASE("a surface that leaves the scene stops training with a clear message, not a normal run" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "r") +
                                   " --steps 20 --gaussians 500 --patch 16 --surface-lr 0.1 --surface-freeze 0 --checkpoint-every 0");
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("the water surface diverged at step") != std::string::npos);
  CHECK(r.output.find("--surface-lr") != std::string::npos);
  CHECK(r.output.find("--surface-batch views") != std::string::npos);
  CHECK(!fs::exists(dir / "r/metrics.json"));

  // With surface batches already on, the message does not advise them again.
  r = test::runCli("train " + data + " -o " + (dir / "b") +
                   " --steps 20 --gaussians 500 --patch 16 --surface-lr 0.3 --surface-freeze 0 --surface-batch 2 --checkpoint-every 0");
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("the water surface diverged at step") != std::string::npos);
  CHECK(r.output.find("one surface step per 2 steps") != std::string::npos);
  CHECK(r.output.find("--surface-batch views") == std::string::npos);
  CHECK(!fs::exists(dir / "b/metrics.json"));
}

TEST_CASE("--resume takes more steps, and refuses options that would change the run" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  std::string run = dir / "r";
  REQUIRE(test::runCli("train " + data + " -o " + run + " --steps 6 --gaussians 200 --patch 16 --checkpoint-every 3").exitCode == 0);
  test::CliResult more = test::runCli("train --resume " + run + " --steps 9");
  INFO(more.output);
  REQUIRE(more.exitCode == 0);
  CHECK(more.output.find("resuming " + run + " at step 6 of 9") != std::string::npos);
  CHECK(readJson(run + "/metrics.json")["step"] == 9);
  CHECK(readJson(run + "/config.json")["steps"] == 9);
  checkOneError(test::runCli("train --resume " + run + " --gaussians 5"), "--gaussians cannot change when a run resumes");
  checkOneError(test::runCli("train --resume " + run + " --steps 4"), "--steps 4 is below the step the run has reached (9");
}

TEST_CASE("a command-line override of water.json is named as the flag, not as the file") {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  for (auto [options, words] : std::vector<std::pair<std::string, std::string>>{
           {"--ior 0.5", "--ior: the index of refraction must be"},
           {"--ior nan", "--ior: the index of refraction must be"},
           {"--domain 1,1,-1,-1", "--domain: the surface domain is empty"},
           {"--water-height inf", "--water-height: the water height is not finite"}}) {
    test::CliResult r = test::runCli("train " + data + " -o " + (dir / "x") + " " + options);
    CAPTURE(options);
    checkOneError(r, words);
    CHECK(r.output.find("water.json") == std::string::npos);
  }
  // a bad value in the file itself is still the file's
  std::string bad = dir / "bad";
  fs::copy(data, bad, fs::copy_options::recursive);
  nlohmann::json w = readJson(bad + "/water.json");
  w["ior"] = 0.5;
  writeJson(bad + "/water.json", w);
  checkOneError(test::runCli("inspect " + bad), bad + "/water.json: the index of refraction must be");
}

TEST_CASE("the synthesiser's LLFF layout loads with its own water.json, as its Blender layout does") {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  std::string llff = dir / "llff";
  fs::create_directories(llff);
  fs::copy(data + "/poses_bounds.npy", llff + "/poses_bounds.npy");
  fs::copy(data + "/images", llff + "/images", fs::copy_options::recursive);
  fs::copy(data + "/water.json", llff + "/water.json");
  test::CliResult r = test::runCli("inspect " + llff);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  Dataset a = loadDataset(llff), b = loadDataset(data);
  CHECK(a.format == "llff");
  CHECK(a.normalization == glm::dmat4(1.0));  // "frame": "dataset": the poses as written
  // every LLFF camera is one of the Blender dataset's cameras
  std::vector<Camera> blender;
  for (const auto& [split, views] : b.splits)
    for (const View& v : views) blender.push_back(v.camera);
  for (const auto& [split, views] : a.splits)
    for (const View& v : views) {
      bool found = false;
      for (const Camera& c : blender) found = found || glm::length(c.position() - v.camera.position()) < 1e-5;
      CHECK_MESSAGE(found, v.name);
    }
  // water.json's frame is checked
  nlohmann::json w = readJson(llff + "/water.json");
  w["frame"] = "world";
  writeJson(llff + "/water.json", w);
  checkOneError(test::runCli("inspect " + llff), "'frame' must be");
}

TEST_CASE("LLFF poses written as integers are refused, not trained as cameras at one point") {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  std::string llff = dir / "ints";
  fs::create_directories(llff);
  fs::copy(data + "/images", llff + "/images", fs::copy_options::recursive);
  NpyArray pb = readNpy(data + "/poses_bounds.npy");
  // the same values as int32 (numpy's astype(int32)): written by hand, as writeNpy writes floats
  std::string header = "{'descr': '<i4', 'fortran_order': False, 'shape': (" + std::to_string(pb.shape[0]) + ", 17), }";
  while ((10 + header.size() + 1) % 64) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += char(header.size() & 0xFF);
  bytes += char(header.size() >> 8);
  bytes += header;
  for (double v : pb.data) {
    int32_t i = int32_t(v);
    bytes.append(reinterpret_cast<const char*>(&i), 4);
  }
  writeFileAtomic(llff + "/poses_bounds.npy", bytes.data(), bytes.size());
  checkOneError(test::runCli("inspect " + llff), "poses_bounds.npy holds integers");
}

TEST_CASE("a PLY whose header counts fewer Gaussians than the file holds is refused") {
  TrainTempDir dir;
  GaussianSet set;
  set.params.assign(500 * kGaussianFloats, 0.0f);
  for (size_t i = 0; i < 500; i++) {
    set.at(i)[f32::kGaussRotation] = 1.0f;
    set.at(i)[f32::kGaussLogScale] = set.at(i)[f32::kGaussLogScale + 1] = set.at(i)[f32::kGaussLogScale + 2] = -3.0f;
  }
  std::string path = dir / "g.ply";
  writeGaussiansPly(path, set);
  std::string bytes = readFile(path);
  size_t at = bytes.find("element vertex 500");
  REQUIRE(at != std::string::npos);
  bytes.replace(at, 18, "element vertex 400");
  std::string edited = dir / "edited.ply";
  writeFileAtomic(edited, bytes.data(), bytes.size());
  CHECK_THROWS_WITH_AS(readGaussiansPly(edited), doctest::Contains("bytes after the 400 Gaussians its header gives"), Error);
  CHECK(readGaussiansPly(path).count() == 500);
  checkOneError(test::runCli("render-gaussians " + edited + " --out " + (dir / "o.png")), "the vertex count is wrong");
}

TEST_CASE("smaller input defects: each one clear error") {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  checkOneError(test::runCli("train " + data + " -o " + (dir / "p") + " --patch 100"), "--patch 100 is larger than the 64 x 64 training images");
  CHECK(!fs::exists(dir / "p"));
  checkOneError(test::runCli("synth nerfrac-primary-sine --size tiny --width 0 -o " + (dir / "s")), "--width must be between 8 and 8192");
  checkOneError(test::runCli("render-gaussians x.ply --out " + (dir / "x.jpg")), "--out must name a .png file");
  checkOneError(test::runCli("train " + data + " -o /proc/refrax-cannot-make-this --steps 2"), "cannot create the folder");
  test::CliResult proc = test::runCli("train " + data + " -o /proc/refrax-cannot-make-this --steps 2");
  CHECK(proc.output.find("filesystem error") == std::string::npos);

  // a malformed glTF's error stays one short line, whatever tinygltf quotes
  std::string gltf = dir / "big.gltf";
  std::ofstream(gltf) << "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 4, \"uri\": \"data:application/octet-stream;base64,"
                      << std::string(3000, 'A') << "\"}], \"meshes\": [ not json";
  std::string run = dir / "run";
  REQUIRE(test::runCli("train " + data + " -o " + run + " --steps 4 --gaussians 200 --patch 16 --checkpoint-every 2").exitCode == 0);
  test::CliResult swap = test::runCli("render " + run + " -o " + (dir / "swap") + " --water " + gltf);
  checkOneError(swap, "is malformed");
  CHECK(swap.output.size() < 600);

  // render -o refuses a folder with files in it, as train -o does
  fs::create_directories(dir / "full");
  std::ofstream(dir / "full/keep.txt") << "x";
  checkOneError(test::runCli("render " + run + " -o " + (dir / "full")), "already exists and is not empty");

  // a corrupted newest checkpoint offers the intact older one
  std::string newest = latestCheckpoint(run);
  REQUIRE(checkpointStep(newest) == 4);
  std::string bytes = readFile(newest);
  bytes[bytes.size() / 2] ^= 0x5a;
  writeFileAtomic(newest, bytes.data(), bytes.size());
  test::CliResult resumed = test::runCli("train --resume " + run + " --steps 6");
  checkOneError(resumed, "corrupted");
  CHECK(resumed.output.find("step_0000002.ckpt is intact: remove") != std::string::npos);
}
