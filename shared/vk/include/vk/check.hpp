// The one Vulkan result check. Records the expression and the source location.
// Setup code uses DHR_VK_CHECK (throws dhr::vk::VulkanError); per-frame code uses
// DHR_VK_TRY, which returns the failing VkResult to the caller after logging it.
#pragma once
#include <vulkan/vulkan.h>

#include <source_location>
#include <stdexcept>
#include <string>

namespace dhr::vk {

const char* result_name(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const char* expression, std::source_location where);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

[[noreturn]] void throw_vk_error(VkResult result, const char* expression,
                                 std::source_location where = std::source_location::current());
void log_vk_error(VkResult result, const char* expression,
                  std::source_location where = std::source_location::current());

}  // namespace dhr::vk

#define DHR_VK_CHECK(expr)                                           \
  do {                                                               \
    const VkResult dhr_vk_result_ = (expr);                          \
    if (dhr_vk_result_ < 0) ::dhr::vk::throw_vk_error(dhr_vk_result_, #expr); \
  } while (0)

#define DHR_VK_TRY(expr)                                             \
  do {                                                               \
    const VkResult dhr_vk_result_ = (expr);                          \
    if (dhr_vk_result_ < 0) {                                        \
      ::dhr::vk::log_vk_error(dhr_vk_result_, #expr);                \
      return dhr_vk_result_;                                         \
    }                                                                \
  } while (0)
