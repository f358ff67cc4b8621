// refrax bench <suite>: dispatches to the suites registered with REFRAX_BENCH_SUITE.
#include "trainer/bench/bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/app/cli.h"

namespace refrax::bench {

namespace {
std::vector<Suite>& registry() {
  static std::vector<Suite> r;
  return r;
}
}  // namespace

void registerSuite(const Suite& suite) { registry().push_back(suite); }
const std::vector<Suite>& suites() { return registry(); }

double medianMs(int warmup, int runs, const std::function<void()>& once) {
  for (int i = 0; i < warmup; i++) once();
  std::vector<double> t;
  for (int i = 0; i < std::max(runs, 1); i++) {
    auto t0 = std::chrono::steady_clock::now();
    once();
    t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

namespace {

std::string suiteList() {
  std::string s;
  for (auto& x : suites()) s += "\n  " + x.name + std::string(x.name.size() < 10 ? 10 - x.name.size() : 1, ' ') + x.summary;
  return s;
}

int runBench(const cli::Args& args) {
  if (args.positional.empty()) fail("refrax bench needs a suite:" + suiteList());
  const std::string& name = args.positional[0];
  for (auto& s : suites())
    if (s.name == name) return s.run(args);
  fail("unknown bench suite '" + name + "'; suites:" + suiteList());
}

// The union of every suite's options, so `refrax bench <suite> --opt` parses; each suite
// documents its own in `refrax bench --help`.
std::vector<cli::Option> allOptions() {
  std::vector<cli::Option> all = cli::deviceOptions();
  for (auto& s : suites())
    for (auto& o : s.options)
      if (std::none_of(all.begin(), all.end(), [&](const cli::Option& x) { return x.name == o.name; })) {
        cli::Option tagged = o;
        tagged.help = "[" + s.name + "] " + o.help;
        all.push_back(tagged);
      }
  return all;
}

REFRAX_COMMAND({"bench", "benchmarks: refrax bench <suite>; speed as ratios measured side by side in one run",
                "refrax bench <suite> [options]   (suites: see refrax bench with no suite)", {}, runBench, allOptions});

}  // namespace

}  // namespace refrax::bench
