// refrax-view in a real window under Xvfb: its render must equal the headless render of the
// same camera, and without a display it must stop with one clear error.
#ifdef REFRAX_VIEWER
#include <doctest/doctest.h>

#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <sys/wait.h>

#include "engine/io/image_io.h"
#include "tests/gpu_test.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {
test::CliResult runShell(const std::string& command) {
  // runCli prefixes the refrax binary; this runs any command line the same way
  std::string cmd = command + " 2>&1";
  test::CliResult r{-1, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while (p && (n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  if (p) {
    int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return r;
}

double maxDifference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) return 1e9;
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); i++) m = std::max(m, double(std::fabs(a.pixels[i] - b.pixels[i])));
  return m;
}
}  // namespace

TEST_CASE("refrax-view under Xvfb renders what refrax preview renders for the same camera") {
  fs::path dir = fs::temp_directory_path() / ("refrax-view-" + std::to_string(test::freshSeed()));
  fs::create_directories(dir);
  std::string shot = (dir / "view.png").string(), ref = (dir / "preview.png").string(), other = (dir / "other.png").string();
  std::string camera = " --camera 0.3,-1.8,1.2,0,0.1,0 --surface triangle --mode wireframe --width 256 --height 192";
  auto v = runShell(std::string("REFRAX_VALIDATION=1 xvfb-run -a ") + REFRAX_VIEWER + " --frames 3 --screenshot " + shot + camera);
  INFO(v.output);
  REQUIRE(v.exitCode == 0);
  CHECK(v.output.find("validation messages: 0") != std::string::npos);
  REQUIRE(test::runCli("preview -o " + ref + camera).exitCode == 0);
  REQUIRE(test::runCli("preview -o " + other + " --camera 0.3,-1.8,1.2,0,0.1,0 --surface sine --width 256 --height 192").exitCode == 0);
  Image a = readPng(shot), b = readPng(ref), c = readPng(other);
  CHECK(maxDifference(a, b) <= 1.0 / 255.0);  // same shader, same inputs: equal up to rounding
  CHECK(maxDifference(a, c) > 0.1);           // and the comparison can tell surfaces apart
  fs::remove_all(dir);
}

TEST_CASE("refrax-view without a display stops with one clear error") {
  auto r = runShell(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + REFRAX_VIEWER + " --frames 1");
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("refrax-view: error: no display") != std::string::npos);
}

TEST_CASE("refrax preview rejects bad arguments with one error") {
  CHECK(test::runCli("preview").exitCode == 1);
  CHECK(test::runCli("preview -o /tmp/x.png --surface lake").output.find("unknown surface 'lake'") != std::string::npos);
  CHECK(test::runCli("preview -o /tmp/x.png --camera 1,2").output.find("must be x,y,z") != std::string::npos);
  CHECK(test::runCli("preview -o /no/such/dir/x.png").exitCode == 1);
}
#endif
