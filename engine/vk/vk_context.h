#pragma once
// The Vulkan instance, the chosen device and its one compute queue.
// Devices are chosen by capability (ray queries, acceleration structures, buffer device
// address, push descriptors; float atomics recorded), or by name/index via --device or
// REFRAX_DEVICE. The Khronos validation layer is on when asked for or REFRAX_VALIDATION=1,
// and every message it sends is counted so that tests can fail on any.
#include <volk.h>

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace refrax {

// How rays find the water and the Gaussians' proxies (issue: every Vulkan GPU).
//   RayQuery: VK_KHR_ray_query against acceleration structures (the driver's BVH);
//   Compute:  plain compute shaders: a walk over the water's grid cells and a software BVH of
//             the proxies' boxes (engine/trace/box_bvh.h), for devices without ray queries (GTX-class
//             and data-centre GPUs, older and mobile GPUs). Both report the same candidates.
enum class TraceBackend { RayQuery, Compute };
const char* traceBackendName(TraceBackend backend);

struct DeviceCaps {
  uint32_t index = 0;
  std::string name;
  std::string driver;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t apiVersion = 0;
  bool bufferDeviceAddress = false;
  bool accelerationStructure = false;
  bool rayQuery = false;
  bool pushDescriptor = false;
  bool floatAtomicAdd = false;        // shaderBufferFloat32AtomicAdd; without it shaders use a CAS loop
  bool sharedFloatAtomicAdd = false;  // shaderSharedFloat32AtomicAdd
  bool shaderFloat64 = false;
  bool timestamps = false;
  bool separateDeviceMemory = false;  // a device-local heap the host cannot map (discrete GPU)
  uint32_t subgroupSize = 0;

  // What this device lacks for a backend (empty: it can run that backend).
  std::vector<std::string> missing(TraceBackend backend) const;
  // What it lacks for either backend (empty: Refrax runs, on the compute backend at least).
  std::vector<std::string> missing() const { return missing(TraceBackend::Compute); }
  bool qualifies() const { return missing().empty(); }
  bool canRun(TraceBackend backend) const { return missing(backend).empty(); }
  std::string typeName() const;
};


struct ContextOptions {
  std::string device;       // name substring or index; empty: REFRAX_DEVICE, else the best device
  // "rayquery", "compute" or "auto" (ray queries where the device has them); empty:
  // REFRAX_TRACE, else auto.
  std::string trace;
  bool validation = false;  // also switched on by REFRAX_VALIDATION=1
  bool verbose = false;     // print the chosen device
  std::vector<const char*> extraDeviceExtensions;    // e.g. VK_KHR_swapchain for the viewer
  std::vector<const char*> extraInstanceExtensions;  // e.g. the window system's surface extensions
};

struct GpuProfiler;
struct Buffer;

struct Context {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  VkCommandPool commandPool = VK_NULL_HANDLE;
  VkCommandBuffer commandBuffer = VK_NULL_HANDLE;  // reused by submitAndWait
  VkFence fence = VK_NULL_HANDLE;
  DeviceCaps caps;
  TraceBackend trace = TraceBackend::RayQuery;  // the backend this context runs (its extensions are enabled for it)
  VkPhysicalDeviceProperties properties{};
  VkPhysicalDeviceMemoryProperties memory{};
  VkPhysicalDeviceAccelerationStructurePropertiesKHR accelProperties{};
  bool validation = false;
  // Tests (and REFRAX_FORCE_STAGING=1) set this to exercise the staging path that discrete
  // GPUs take on a device whose memory the host could map directly (lavapipe).
  bool forceStaging = false;
  // Set while a run is profiled (engine/vk/vk_profile.h): submitAndWait times every submission.
  GpuProfiler* profiler = nullptr;
  // Submissions not yet waited for (submitWithoutWait, engine/vk/vk_commands.h), oldest first:
  // each one's fence and what to do once it has signalled.
  struct InFlight {
    VkFence fence = VK_NULL_HANDLE;
    std::function<void()> done;
  };
  std::deque<InFlight> inFlight;
  // The host-visible buffer upload and download copy through on a device the host cannot
  // map (engine/vk/vk_buffer.cpp stagingFor), kept and grown rather than made per call.
  std::unique_ptr<Buffer> staging;

  // Validation messages seen so far (warnings and errors of every type).
  std::atomic<int> validationMessageCount{0};
  std::mutex messageMutex;
  std::vector<std::string> validationMessages;

  Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context();
};

// Every Vulkan device the loader sees, with what each offers.
std::vector<DeviceCaps> listDevices();
std::unique_ptr<Context> createContext(const ContextOptions& options = {});
// A primary command buffer from the context's pool, and a fence (signalled: already set).
VkCommandBuffer allocateCommandBuffer(Context& ctx);
VkFence createFence(Context& ctx, bool signalled = false);
// "refrax: device [i] NAME (DRIVER), BACKEND trace[, validation on]" on stderr: what
// createContext prints when verbose (a command that checks its input after opening the device
// prints it once the input has passed).
void printContextLine(const Context& ctx);

// Validation messages sent to any context of this process so far, including those sent
// while a context is destroyed (leaked objects).
int processValidationMessageCount();

// Validation messages since the last call, cleared.
std::vector<std::string> takeValidationMessages(Context& ctx);

}  // namespace refrax
