// refrax devices: every Vulkan device, what it offers and what it lacks.
#include <cstdio>

#include "engine/vk/vk_context.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runDevices(const cli::Args&) {
  auto devices = listDevices();
  if (devices.empty()) {
    std::printf("no Vulkan devices found\n");
    return 1;
  }
  auto yes = [](bool b) { return b ? "yes" : "no"; };
  bool any = false;
  for (auto& d : devices) {
    std::printf("[%u] %s (%s), Vulkan %u.%u.%u, driver %s\n", d.index, d.name.c_str(), d.typeName().c_str(),
                VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion), VK_API_VERSION_PATCH(d.apiVersion),
                d.driver.c_str());
    std::printf("    ray query %s, acceleration structures %s, buffer device address %s, push descriptors %s\n", yes(d.rayQuery),
                yes(d.accelerationStructure), yes(d.bufferDeviceAddress), yes(d.pushDescriptor));
    std::printf("    float atomic add: buffer %s, shared %s%s; timestamps %s; subgroup %u; %s memory\n", yes(d.floatAtomicAdd),
                yes(d.sharedFloatAtomicAdd), d.floatAtomicAdd ? "" : " (compare-and-swap fallback)", yes(d.timestamps),
                d.subgroupSize, d.separateDeviceMemory ? "separate device" : "shared host/device");
    auto missing = d.missing();
    if (missing.empty()) {
      std::printf("    qualifies for Refrax\n");
      any = true;
      // the trace backends it can run (--trace, REFRAX_TRACE), and why not
      for (TraceBackend b : {TraceBackend::RayQuery, TraceBackend::Compute}) {
        auto lacks = d.missing(b);
        std::printf("    trace %-8s %s", traceBackendName(b), lacks.empty() ? "yes" : "no: lacks");
        for (size_t i = 0; i < lacks.size(); i++) std::printf("%s %s", i ? "," : "", lacks[i].c_str());
        std::printf("%s\n", lacks.empty() && (b == TraceBackend::RayQuery || !d.canRun(TraceBackend::RayQuery)) ? " (auto's choice)" : "");
      }
    } else {
      std::printf("    cannot run Refrax: lacks");
      for (size_t i = 0; i < missing.size(); i++) std::printf("%s %s", i ? "," : "", missing[i].c_str());
      std::printf("\n");
    }
  }
  return any ? 0 : 1;
}

REFRAX_COMMAND({"devices", "list Vulkan devices with what each supports and lacks", "refrax devices", {}, runDevices});

}  // namespace
}  // namespace refrax
