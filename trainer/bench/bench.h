#pragma once
// `refrax bench <suite>`: each suite registers itself from its own file with REFRAX_BENCH_SUITE
// and gets the options it declares (plus --device/--validation) parsed for it.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "engine/app/cli.h"

namespace refrax::bench {

struct Suite {
  std::string name;
  std::string summary;
  std::vector<cli::Option> options;  // the suite's own; device options are added
  int (*run)(const cli::Args&);
};

void registerSuite(const Suite& suite);
const std::vector<Suite>& suites();

struct SuiteRegistrar {
  explicit SuiteRegistrar(const Suite& s) { registerSuite(s); }
};

// Runs the rqprobe binary `probe` (lavapipe unless VK_ICD_FILENAMES says otherwise) with
// `args`; returns its `RESULT name value` lines (and the k-buffer runs' CPU times).
std::map<std::string, double> runProbe(const std::string& probe, const std::string& args);

// Median of `runs` calls of `once()` (milliseconds) after `warmup` calls.
double medianMs(int warmup, int runs, const std::function<void()>& once);

}  // namespace refrax::bench

#define REFRAX_BENCH_SUITE(...) \
  static ::refrax::bench::SuiteRegistrar REFRAX_CLI_CONCAT(refraxBenchSuite_, __LINE__)(::refrax::bench::Suite __VA_ARGS__)
