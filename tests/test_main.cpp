#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sys/wait.h>

#include "tests/gpu_test.h"

namespace refrax::test {

namespace {
std::unique_ptr<Context> g_context;
}

Context& context() {
  if (!g_context) {
    ContextOptions o;
    o.validation = true;
    g_context = createContext(o);
  }
  return *g_context;
}

uint32_t freshSeed() {
  if (const char* s = std::getenv("REFRAX_TEST_SEED")) return uint32_t(std::strtoul(s, nullptr, 10));
  return uint32_t(std::chrono::steady_clock::now().time_since_epoch().count());
}

GpuTest::GpuTest() : ctx(context()) {
  takeValidationMessages(ctx);
  uint32_t seed = freshSeed();
  MESSAGE("seed " << seed << " (replay with REFRAX_TEST_SEED=" << seed << ")");
  rng.seed(seed);
}

GpuTest::~GpuTest() {
  auto messages = takeValidationMessages(ctx);
  CHECK_MESSAGE(messages.empty(), "validation layer: " << (messages.empty() ? "" : messages.front()));
}

CliResult runCli(const std::string& arguments) {
  std::string cmd = std::string(REFRAX_CLI) + " " + arguments + " 2>&1";
  CliResult r{-1, ""};
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  int status = pclose(p);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace refrax::test

int main(int argc, char** argv) {
  doctest::Context runner;
  runner.applyCommandLine(argc, argv);
  int result = runner.run();
  // Destroying the device lets the layer report leaked objects; those fail the run too.
  int before = refrax::processValidationMessageCount();
  refrax::test::g_context.reset();
  int atTeardown = refrax::processValidationMessageCount() - before;
  if (atTeardown > 0) {
    std::fprintf(stderr, "%d validation message(s) while destroying the device\n", atTeardown);
    return 1;
  }
  return result;
}
