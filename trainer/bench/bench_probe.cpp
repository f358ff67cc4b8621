// The rqprobe run as a subprocess (its shaders beside it), its RESULT lines parsed: the
// raw-rate floor that `refrax bench rays` and `refrax bench tracer` compare with.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "engine/base/error.h"
#include "trainer/bench/bench.h"

namespace refrax::bench {

std::map<std::string, double> runProbe(const std::string& probe, const std::string& args) {
  std::string dir = probe.substr(0, probe.find_last_of('/') + 1);
  std::string cmd = "cd '" + (dir.empty() ? std::string(".") : dir) +
                    "' && VK_ICD_FILENAMES=${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.json} SPV_DIR=shaders '" + probe + "' " + args +
                    " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) fail("cannot run the probe " + probe);
  std::map<std::string, double> out;
  char line[1024];
  while (std::fgets(line, sizeof line, p)) {
    char name[256];
    double v;
    if (std::sscanf(line, "RESULT %255s %lf", name, &v) == 2) out[name] = v;
    // the k-buffer lines also give the process CPU time of the median run
    std::string l(line);
    size_t cpu = l.find("cpu ");
    if (cpu != std::string::npos && l.find("k-buffer K=16") != std::string::npos)
      out[l.find("commit") != std::string::npos ? "kbuf_commit_cpu_ms" : "kbuf_cpu_ms"] = std::atof(l.c_str() + cpu + 4);
  }
  if (pclose(p) != 0) fail("the probe failed (" + cmd + ")");
  return out;
}

}  // namespace refrax::bench
