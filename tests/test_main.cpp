#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
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
  // REFRAX_CLI: a refrax binary elsewhere (a build copied to another machine, scripts/gpu-check.sh)
  const char* cli = std::getenv("REFRAX_CLI");
  return runShell(std::string(cli ? cli : REFRAX_CLI) + " " + arguments);
}

CliResult runShell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
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

namespace {
// Counts the cases that ran, so that a filter matching nothing (e.g. a CTest name that lost
// part of the case name) fails instead of passing vacuously.
int g_casesRun = 0;
struct CaseCounter : doctest::IReporter {
  explicit CaseCounter(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData&) override { g_casesRun++; }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};
REGISTER_LISTENER("case-counter", 1, CaseCounter);
}  // namespace

int main(int argc, char** argv) {
  // Every case, and every CLI it runs, with the validation layer on (CTest sets it too; a
  // direct run of this binary gets the same).
  setenv("REFRAX_VALIDATION", "1", 0);
  // The compute-backend pass stands for a GPU without ray queries: it orders the Gaussians'
  // proxies on the device as a GPU does, where lavapipe orders them on the host
  // (engine/gaussian/gaussian_trace.h orderOnDevice; tests/CMakeLists.txt).
  if (const char* trace = std::getenv("REFRAX_TRACE"); trace && std::string(trace) == "compute") setenv("REFRAX_PROXY_ORDER", "device", 0);
  doctest::Context runner;
  runner.applyCommandLine(argc, argv);
  int result = runner.run();
  bool listing = false;
  for (int i = 1; i < argc; i++) listing |= std::string(argv[i]).find("-l") == 0 || std::string(argv[i]).find("--list") == 0;
  if (!listing && !runner.shouldExit() && g_casesRun == 0) {
    std::fprintf(stderr, "no test case matched the filter: failing rather than passing vacuously\n");
    return 1;
  }
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
