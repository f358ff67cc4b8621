#include "engine/vk/vk_context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "engine/base/error.h"
#include "engine/vk/vk_buffer.h"  // ~Context releases the staging Buffer

namespace refrax {

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::atomic<int> g_processMessages{0};

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

void initLoader() {
  static bool loaded = false;
  if (loaded) return;
  if (volkInitialize() != VK_SUCCESS)
    fail("no Vulkan loader found (libvulkan.so.1); install libvulkan1 and a driver, e.g. mesa-vulkan-drivers");
  loaded = true;
}

bool hasLayer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* user) {
  auto* ctx = static_cast<Context*>(user);
  const char* level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
  std::string msg = std::string("validation ") + level + ": " + (data && data->pMessage ? data->pMessage : "(no text)");
  std::fprintf(stderr, "%s\n", msg.c_str());
  g_processMessages++;
  if (ctx) {
    std::lock_guard<std::mutex> lock(ctx->messageMutex);
    ctx->validationMessages.push_back(msg);
    ctx->validationMessageCount++;
  }
  return VK_FALSE;
}

VkInstance createInstance(bool validation, Context* ctx, VkDebugUtilsMessengerEXT* messenger,
                          const std::vector<const char*>& extraExtensions = {}) {
  initLoader();
  uint32_t loaderVersion = 0;
  if (vkEnumerateInstanceVersion) vkEnumerateInstanceVersion(&loaderVersion);
  if (loaderVersion < VK_API_VERSION_1_2) fail("the Vulkan loader is older than 1.2; Refrax needs Vulkan 1.2 or newer");

  std::vector<const char*> layers, extensions(extraExtensions);
  VkDebugUtilsMessengerCreateInfoEXT dmi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  dmi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  dmi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  dmi.pfnUserCallback = onValidationMessage;
  dmi.pUserData = ctx;
  if (validation) {
    if (!hasLayer(kValidationLayer))
      fail("validation was requested but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "refrax";
  app.pEngineName = "refrax";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pNext = validation ? &dmi : nullptr;  // also catches messages from instance creation itself
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = uint32_t(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = uint32_t(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ici, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    fail("no Vulkan driver is installed; install one (on Debian: mesa-vulkan-drivers from bookworm-backports for lavapipe)");
  REFRAX_VK(r);
  volkLoadInstance(instance);
  if (validation && messenger) REFRAX_VK(vkCreateDebugUtilsMessengerEXT(instance, &dmi, nullptr, messenger));
  return instance;
}

bool hasExtension(const std::vector<VkExtensionProperties>& exts, const char* name) {
  for (auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

DeviceCaps queryCaps(VkPhysicalDevice pd, uint32_t index) {
  DeviceCaps c;
  c.index = index;
  uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());

  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &driver};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroup};
  vkGetPhysicalDeviceProperties2(pd, &props);
  c.name = props.properties.deviceName;
  c.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  c.type = props.properties.deviceType;
  c.apiVersion = props.properties.apiVersion;
  c.subgroupSize = subgroup.subgroupSize;
  c.timestamps = props.properties.limits.timestampComputeAndGraphics;

  bool hasAS = hasExtension(exts, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
               hasExtension(exts, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  bool hasRQ = hasExtension(exts, VK_KHR_RAY_QUERY_EXTENSION_NAME);
  bool hasAF = hasExtension(exts, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  c.pushDescriptor = hasExtension(exts, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT af{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  // Chain only structures whose extension exists: unknown structures are invalid usage.
  void** tail = &f2.pNext;
  if (c.apiVersion >= VK_API_VERSION_1_2) { *tail = &v12; tail = &v12.pNext; }
  if (hasAS) { *tail = &as; tail = &as.pNext; }
  if (hasRQ) { *tail = &rq; tail = &rq.pNext; }
  if (hasAF) { *tail = &af; tail = &af.pNext; }
  vkGetPhysicalDeviceFeatures2(pd, &f2);
  c.bufferDeviceAddress = v12.bufferDeviceAddress;
  c.accelerationStructure = hasAS && as.accelerationStructure;
  c.rayQuery = hasRQ && rq.rayQuery;
  c.floatAtomicAdd = hasAF && af.shaderBufferFloat32AtomicAdd;
  c.sharedFloatAtomicAdd = hasAF && af.shaderSharedFloat32AtomicAdd;
  c.shaderFloat64 = f2.features.shaderFloat64;

  VkPhysicalDeviceMemoryProperties mem;
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);
  bool deviceOnly = false;
  for (uint32_t i = 0; i < mem.memoryTypeCount; i++) {
    auto f = mem.memoryTypes[i].propertyFlags;
    if ((f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) && !(f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)) deviceOnly = true;
  }
  c.separateDeviceMemory = deviceOnly;
  return c;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return s;
}

int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

std::string describeAll(const std::vector<DeviceCaps>& all) {
  std::string s;
  for (auto& c : all) {
    s += "\n  [" + std::to_string(c.index) + "] " + c.name + " (" + c.typeName() + "): ";
    auto m = c.missing();
    if (m.empty()) {
      s += "qualifies";
    } else {
      s += "lacks ";
      for (size_t i = 0; i < m.size(); i++) s += (i ? ", " : "") + m[i];
    }
  }
  return s;
}

}  // namespace

const char* traceBackendName(TraceBackend backend) { return backend == TraceBackend::RayQuery ? "rayquery" : "compute"; }

std::vector<std::string> DeviceCaps::missing(TraceBackend backend) const {
  std::vector<std::string> m;
  if (apiVersion < VK_API_VERSION_1_2) m.push_back("Vulkan 1.2");
  if (!bufferDeviceAddress) m.push_back("bufferDeviceAddress");
  if (backend == TraceBackend::RayQuery && !accelerationStructure) m.push_back("VK_KHR_acceleration_structure");
  if (backend == TraceBackend::RayQuery && !rayQuery) m.push_back("VK_KHR_ray_query");
  if (!pushDescriptor) m.push_back("VK_KHR_push_descriptor");
  return m;
}

std::string DeviceCaps::typeName() const {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

std::vector<DeviceCaps> listDevices() {
  VkInstance instance = createInstance(false, nullptr, nullptr);
  uint32_t n = 0;
  vkEnumeratePhysicalDevices(instance, &n, nullptr);
  std::vector<VkPhysicalDevice> pds(n);
  vkEnumeratePhysicalDevices(instance, &n, pds.data());
  std::vector<DeviceCaps> out;
  for (uint32_t i = 0; i < n; i++) out.push_back(queryCaps(pds[i], i));
  vkDestroyInstance(instance, nullptr);
  return out;
}

namespace {

// --device NAME|INDEX (or REFRAX_DEVICE), else the device most able: one with ray queries
// before one without, then by kind. Returns its index in `all`.
int chooseDevice(const std::vector<DeviceCaps>& all, std::string want) {
  if (want.empty() && std::getenv("REFRAX_DEVICE")) want = std::getenv("REFRAX_DEVICE");
  int chosen = -1;
  if (!want.empty()) {
    bool numeric = want.find_first_not_of("0123456789") == std::string::npos;
    for (auto& c : all)
      if ((numeric && std::to_string(c.index) == want) || (!numeric && lower(c.name).find(lower(want)) != std::string::npos)) {
        chosen = int(c.index);
        break;
      }
    if (chosen < 0) fail("no Vulkan device matches '" + want + "'; devices seen:" + describeAll(all));
    if (!all[chosen].qualifies())
      fail("device '" + all[chosen].name + "' cannot run Refrax; devices seen:" + describeAll(all));
    return chosen;
  }
  auto rank = [](const DeviceCaps& c) { return (c.canRun(TraceBackend::RayQuery) ? 10 : 0) + typeRank(c.type); };
  for (auto& c : all)
    if (c.qualifies() && (chosen < 0 || rank(c) > rank(all[chosen]))) chosen = int(c.index);
  if (chosen < 0)
    fail("no Vulkan device offers what Refrax needs (Vulkan 1.2 compute with buffer device addresses and push "
         "descriptors); devices seen:" + describeAll(all) +
         "\n  (on a CPU, install mesa-vulkan-drivers >= 24 from bookworm-backports for lavapipe)");
  return chosen;
}

// --trace (or REFRAX_TRACE): rayquery, compute or auto (ray queries where the device has them).
TraceBackend chooseTrace(const DeviceCaps& caps, std::string trace) {
  if (trace.empty() && std::getenv("REFRAX_TRACE")) trace = std::getenv("REFRAX_TRACE");
  if (trace.empty()) trace = "auto";
  if (trace == "auto") return caps.canRun(TraceBackend::RayQuery) ? TraceBackend::RayQuery : TraceBackend::Compute;
  if (trace != "rayquery" && trace != "compute")
    fail("the trace backend must be rayquery, compute or auto (--trace or REFRAX_TRACE), not '" + trace + "'");
  TraceBackend backend = trace == "rayquery" ? TraceBackend::RayQuery : TraceBackend::Compute;
  if (!caps.canRun(backend)) {
    std::string lacks;
    for (const std::string& m : caps.missing(backend)) lacks += (lacks.empty() ? "" : ", ") + m;
    fail("device '" + caps.name + "' cannot run the " + trace + " trace backend (it lacks " + lacks + "); --trace compute or auto runs on it");
  }
  return backend;
}

// A compute queue family, preferring one that also does graphics (the viewer presents from
// it); a family without timestamps switches the device's timestamps off.
void chooseQueueFamily(Context& ctx) {
  uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> families(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical, &nq, families.data());
  int family = -1;
  for (uint32_t i = 0; i < nq; i++)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      if (family < 0 || (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) family = int(i);
      if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) break;
    }
  if (family < 0) fail("device '" + ctx.caps.name + "' has no compute queue");
  ctx.queueFamily = uint32_t(family);
  if (!families[family].timestampValidBits) ctx.caps.timestamps = false;
}

// The logical device with the extensions and features the chosen trace backend uses, and its queue.
void createDevice(Context& ctx, const std::vector<const char*>& extraExtensions) {
  // The acceleration-structure extensions only for the ray-query backend: the compute backend
  // runs as on a device without them (and validation reports any use of them).
  const bool rayQueries = ctx.trace == TraceBackend::RayQuery;
  const bool floatAtomics = ctx.caps.floatAtomicAdd || ctx.caps.sharedFloatAtomicAdd;
  std::vector<const char*> exts = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  if (rayQueries)
    for (const char* e : {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, VK_KHR_RAY_QUERY_EXTENSION_NAME, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME})
      exts.push_back(e);
  if (floatAtomics) exts.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  for (const char* extra : extraExtensions) exts.push_back(extra);

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT af{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  af.shaderBufferFloat32Atomics = ctx.caps.floatAtomicAdd;
  af.shaderBufferFloat32AtomicAdd = ctx.caps.floatAtomicAdd;
  af.shaderSharedFloat32Atomics = ctx.caps.sharedFloatAtomicAdd;
  af.shaderSharedFloat32AtomicAdd = ctx.caps.sharedFloatAtomicAdd;
  VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  rq.rayQuery = VK_TRUE;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, &rq};
  as.accelerationStructure = VK_TRUE;
  if (floatAtomics) rq.pNext = &af;
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &as};
  if (!rayQueries) v12.pNext = floatAtomics ? static_cast<void*>(&af) : nullptr;
  v12.bufferDeviceAddress = VK_TRUE;
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
  f2.features.shaderInt64 = VK_FALSE;
  f2.features.shaderFloat64 = VK_FALSE;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = ctx.queueFamily;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &f2};
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.enabledExtensionCount = uint32_t(exts.size());
  dci.ppEnabledExtensionNames = exts.data();
  REFRAX_VK(vkCreateDevice(ctx.physical, &dci, nullptr, &ctx.device));
  // Device functions stay the loader's (volkLoadInstance loaded them through vkGetInstanceProcAddr),
  // which dispatch on the device handle: volkLoadDevice would bind every later call to this
  // device's driver entries, and a second context (another device, or the other trace
  // backend without the acceleration-structure extension) would call through the wrong ones.
  vkGetDeviceQueue(ctx.device, ctx.queueFamily, 0, &ctx.queue);
}

// The context's own command pool, command buffer and fence (submitAndWait).
void createCommandObjects(Context& ctx) {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = ctx.queueFamily;
  REFRAX_VK(vkCreateCommandPool(ctx.device, &pci, nullptr, &ctx.commandPool));
  ctx.commandBuffer = allocateCommandBuffer(ctx);
  ctx.fence = createFence(ctx);
}

}  // namespace

VkCommandBuffer allocateCommandBuffer(Context& ctx) {
  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = ctx.commandPool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  REFRAX_VK(vkAllocateCommandBuffers(ctx.device, &cai, &cb));
  return cb;
}

VkFence createFence(Context& ctx, bool signalled) {
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (signalled) fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VkFence fence = VK_NULL_HANDLE;
  REFRAX_VK(vkCreateFence(ctx.device, &fci, nullptr, &fence));
  return fence;
}

std::unique_ptr<Context> createContext(const ContextOptions& options) {
  auto ctx = std::make_unique<Context>();
  ctx->validation = options.validation || envFlag("REFRAX_VALIDATION");
  // REFRAX_FORCE_STAGING=1: every transfer through the staging buffer, a submission each, as a
  // discrete GPU moves them, so that lavapipe counts a step's submissions as such a GPU would.
  ctx->forceStaging = envFlag("REFRAX_FORCE_STAGING");
  ctx->instance = createInstance(ctx->validation, ctx.get(), &ctx->messenger, options.extraInstanceExtensions);

  uint32_t n = 0;
  vkEnumeratePhysicalDevices(ctx->instance, &n, nullptr);
  std::vector<VkPhysicalDevice> pds(n);
  vkEnumeratePhysicalDevices(ctx->instance, &n, pds.data());
  if (n == 0) fail("no Vulkan device found; install a driver (on Debian: mesa-vulkan-drivers from bookworm-backports)");
  std::vector<DeviceCaps> all;
  for (uint32_t i = 0; i < n; i++) all.push_back(queryCaps(pds[i], i));
  int chosen = chooseDevice(all, options.device);
  ctx->physical = pds[chosen];
  ctx->caps = all[chosen];
  ctx->trace = chooseTrace(ctx->caps, options.trace);

  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  ctx->accelProperties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
  if (ctx->caps.accelerationStructure) props.pNext = &ctx->accelProperties;  // an unknown structure is invalid usage
  vkGetPhysicalDeviceProperties2(ctx->physical, &props);
  ctx->properties = props.properties;
  vkGetPhysicalDeviceMemoryProperties(ctx->physical, &ctx->memory);

  chooseQueueFamily(*ctx);
  createDevice(*ctx, options.extraDeviceExtensions);
  createCommandObjects(*ctx);
  if (options.verbose) printContextLine(*ctx);
  return ctx;
}

void printContextLine(const Context& ctx) {
  std::fprintf(stderr, "refrax: device [%u] %s (%s), %s trace%s\n", ctx.caps.index, ctx.caps.name.c_str(), ctx.caps.driver.c_str(),
               traceBackendName(ctx.trace), ctx.validation ? ", validation on" : "");
}

Context::~Context() {
  if (device) {
    vkDeviceWaitIdle(device);
    staging.reset();  // a Buffer of this device: released before it
    if (fence) vkDestroyFence(device, fence, nullptr);
    if (commandPool) vkDestroyCommandPool(device, commandPool, nullptr);
    vkDestroyDevice(device, nullptr);
  }
  if (messenger) vkDestroyDebugUtilsMessengerEXT(instance, messenger, nullptr);
  if (instance) vkDestroyInstance(instance, nullptr);
}

int processValidationMessageCount() { return g_processMessages.load(); }

std::vector<std::string> takeValidationMessages(Context& ctx) {
  std::lock_guard<std::mutex> lock(ctx.messageMutex);
  std::vector<std::string> out;
  out.swap(ctx.validationMessages);
  return out;
}

}  // namespace refrax
