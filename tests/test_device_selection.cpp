// Device choice by name/index, and the clear error when nothing matches.
#include <doctest/doctest.h>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"
#include "tests/gpu_test.h"

using namespace refrax;

// CI's lavapipe must offer ray queries, or the rayquery backend would go untested there; a GPU
// without them (the H200's driver, 2026-11-27) runs the suite on the compute backend.
static bool isLavapipe(const DeviceCaps& caps) { return caps.name.find("llvmpipe") != std::string::npos; }

TEST_CASE("the test device qualifies, and lavapipe offers ray queries") {
  Context& ctx = test::context();
  CHECK(ctx.caps.qualifies());
  if (isLavapipe(ctx.caps)) {
    CHECK(ctx.caps.rayQuery);
    CHECK(ctx.caps.accelerationStructure);
  }
  CHECK(ctx.caps.canRun(TraceBackend::RayQuery) == ctx.caps.rayQuery);
}

TEST_CASE("asking for a device that does not exist is one clear error") {
  ContextOptions o;
  o.device = "no-such-device-xyz";
  try {
    createContext(o);
    FAIL("createContext accepted a device that does not exist");
  } catch (const Error& e) {
    std::string m = e.what();
    CHECK(m.find("no Vulkan device matches 'no-such-device-xyz'") != std::string::npos);
    CHECK(m.find("[0]") != std::string::npos);  // lists the devices seen
  }
  o.device = "99";
  CHECK_THROWS_AS(createContext(o), Error);
}

TEST_CASE("the CLI reports a missing device with one error line and a non-zero exit") {
  auto r = test::runCli("selftest --device no-such-device-xyz");
  CHECK(r.exitCode == 1);
  CHECK(r.output.rfind("refrax: error: no Vulkan device matches 'no-such-device-xyz'", 0) == 0);
  CHECK(r.output.find("Segmentation") == std::string::npos);
}

TEST_CASE("the CLI rejects unknown commands and options") {
  CHECK(test::runCli("no-such-command").exitCode == 2);
  auto r = test::runCli("selftest --no-such-option");
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("unknown option --no-such-option") != std::string::npos);
}

TEST_CASE("refrax devices lists the device with its capabilities") {
  auto r = test::runCli("devices");
  CHECK(r.exitCode == 0);
  CHECK(r.output.find(test::context().caps.rayQuery ? "ray query yes" : "ray query no") != std::string::npos);
  CHECK(r.output.find("qualifies for Refrax") != std::string::npos);
}

TEST_CASE("refrax selftest passes with validation on") {
  auto r = test::runCli("selftest --validation");
  INFO(r.output);
  CHECK(r.exitCode == 0);
  CHECK(r.output.find("validation messages: 0") != std::string::npos);
  CHECK(r.output.find("selftest passed") != std::string::npos);
}

TEST_CASE("the trace backend is chosen by --trace or REFRAX_TRACE, a bad name is one clear error, and devices lists both") {
  ContextOptions o;
  o.trace = "compute";
  auto compute = createContext(o);
  CHECK(compute->trace == TraceBackend::Compute);
  const bool rayQuery = test::context().caps.rayQuery;  // lavapipe offers them; the H200's driver does not
  o.trace = "auto";
  CHECK(createContext(o)->trace == (rayQuery ? TraceBackend::RayQuery : TraceBackend::Compute));
  o.trace = "raytracing";
  CHECK_THROWS_WITH_AS(createContext(o), doctest::Contains("must be rayquery, compute or auto"), Error);
  auto r = test::runCli("devices");
  INFO(r.output);
  if (rayQuery) {
    CHECK(r.output.find("trace rayquery yes (auto's choice)") != std::string::npos);
    CHECK(r.output.find("trace compute  yes") != std::string::npos);
  } else {
    CHECK(r.output.find("trace rayquery no: lacks VK_KHR_ray_query") != std::string::npos);
    CHECK(r.output.find("trace compute  yes (auto's choice)") != std::string::npos);
  }
  auto s = test::runCli("selftest --validation --trace compute");
  INFO(s.output);
  CHECK(s.exitCode == 0);
  CHECK(s.output.find("selftest passed") != std::string::npos);
  CHECK(s.output.find("(compute trace)") != std::string::npos);
  CHECK(s.output.find("validation messages: 0") != std::string::npos);
  auto bad = test::runCli("selftest --trace optix");
  CHECK(bad.exitCode == 1);
  CHECK(bad.output.find("the trace backend must be rayquery, compute or auto") != std::string::npos);
}
