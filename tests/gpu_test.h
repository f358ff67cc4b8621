#pragma once
// Test fixture for everything that touches the device: one validated context per test
// process, and a check after every case that the validation layer said nothing.
#include <doctest/doctest.h>

#include <random>
#include <string>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax::test {

Context& context();  // created on first use, validation on, device from REFRAX_DEVICE

// A seed that differs per run (so random inputs are fresh) unless REFRAX_TEST_SEED is set;
// printed so a failure can be replayed.
uint32_t freshSeed();

struct GpuTest {
  Context& ctx;
  std::mt19937 rng;
  GpuTest();
  ~GpuTest();
};

// Runs the `refrax` CLI with `arguments`; returns its exit code and combined output.
struct CliResult {
  int exitCode;
  std::string output;
};
CliResult runCli(const std::string& arguments);
// Any shell command (another tool: gdalinfo, colmap), its stdout and stderr together.
CliResult runShell(const std::string& command);

}  // namespace refrax::test

#define GPU_TEST_CASE(name) TEST_CASE_FIXTURE(::refrax::test::GpuTest, name)
