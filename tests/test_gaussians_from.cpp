// --gaussians-from and --gaussians-fixed (engine/run/train_config.h): the study of the water's
// chain with the Gaussians held at a fit that is already right (issue 45). The Gaussians read
// are the run's first ones; fixed, they leave the run byte for byte as they came, while the
// water learns.
#include <doctest/doctest.h>

#include <filesystem>

#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/gaussian/ply_gaussians.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace fs = std::filesystem;
using namespace refrax;

TEST_CASE("--gaussians-fixed keeps the Gaussians read with --gaussians-from while the water learns" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string first = dir / "first";
  REQUIRE(test::runCli("train " + data + " -o " + first + " --steps 4 --gaussians 300 --patch 16 --checkpoint-every 0").exitCode == 0);
  const std::string ply = first + "/point_cloud.ply";

  // Fixed: the same bytes out as in (PLY -> table -> PLY is exact), every step's surface steps taken.
  const std::string fixed = dir / "fixed";
  test::CliResult r = test::runCli("train " + data + " -o " + fixed + " --steps 12 --patch 16 --surface-freeze 0 --checkpoint-every 0 --gaussians-from " +
                                   ply + " --gaussians-fixed");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(readFile(fixed + "/point_cloud.ply") == readFile(ply));
  const nlohmann::json config = readJson(fixed + "/config.json");
  CHECK(config["initial_gaussians"] == 300);  // the file's count, not the data's sizing
  CHECK(config["gaussians_fixed"] == true);
  CHECK(config["gaussians_from"] == fs::absolute(ply).lexically_normal().string());
  // the water moved off the flat start
  const NpyArray heights = readNpy(fixed + "/water_height.npy");
  double lo = heights.data.front(), hi = lo;
  for (double h : heights.data) lo = std::min(lo, h), hi = std::max(hi, h);
  CHECK(hi - lo > 1e-5);

  // Read but not fixed: they start as read and learn.
  const std::string learned = dir / "learned";
  REQUIRE(test::runCli("train " + data + " -o " + learned + " --steps 3 --patch 16 --checkpoint-every 0 --gaussians-from " + ply).exitCode == 0);
  CHECK(readGaussiansPly(learned + "/point_cloud.ply").count() == 300);
  CHECK(readFile(learned + "/point_cloud.ply") != readFile(ply));

  // Fixed Gaussians need a file; a file replaces the other ways of placing them.
  r = test::runCli("train " + data + " -o " + (dir / "no") + " --steps 2 --gaussians-fixed");
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("--gaussians-fixed needs --gaussians-from PLY") != std::string::npos);
  r = test::runCli("train " + data + " -o " + (dir / "no") + " --steps 2 --gaussians-from " + ply + " --init-depth sweep");
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("takes no --init-points or --init-depth") != std::string::npos);
  r = test::runCli("train " + data + " -o " + (dir / "no") + " --steps 2 --gaussians-from " + (dir / "missing.ply"));
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("missing.ply") != std::string::npos);
  CHECK(!fs::exists(dir / "no"));
}
