#pragma once
// One error type for everything a user can cause or meet (bad input, missing device);
// the CLI prints what() as a single line and exits non-zero.
#include <stdexcept>
#include <string>

namespace refrax {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& message);

// Vulkan call that must succeed; the message names the call and the VkResult.
#define REFRAX_VK(call)                                                              \
  do {                                                                               \
    VkResult refrax_vk_result_ = (call);                                             \
    if (refrax_vk_result_ != VK_SUCCESS)                                             \
      ::refrax::failVk(#call, refrax_vk_result_, __FILE__, __LINE__);                \
  } while (0)

[[noreturn]] void failVk(const char* call, int result, const char* file, int line);
const char* vkResultName(int result);

}  // namespace refrax
