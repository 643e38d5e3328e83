#include "vk/check.hpp"

#include <cstdio>
#include <cstring>
#include <string_view>

#include "log/log.hpp"

namespace dhr::vk {

const char* result_name(VkResult result) {
  switch (result) {
#define DHR_VK_RESULT_CASE(name) \
  case name:                     \
    return #name;
    DHR_VK_RESULT_CASE(VK_SUCCESS)
    DHR_VK_RESULT_CASE(VK_NOT_READY)
    DHR_VK_RESULT_CASE(VK_TIMEOUT)
    DHR_VK_RESULT_CASE(VK_EVENT_SET)
    DHR_VK_RESULT_CASE(VK_EVENT_RESET)
    DHR_VK_RESULT_CASE(VK_INCOMPLETE)
    DHR_VK_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    DHR_VK_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    DHR_VK_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    DHR_VK_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    DHR_VK_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    DHR_VK_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    DHR_VK_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    DHR_VK_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    DHR_VK_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    DHR_VK_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    DHR_VK_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    DHR_VK_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    DHR_VK_RESULT_CASE(VK_ERROR_UNKNOWN)
    DHR_VK_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    DHR_VK_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    DHR_VK_RESULT_CASE(VK_ERROR_FRAGMENTATION)
    DHR_VK_RESULT_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    DHR_VK_RESULT_CASE(VK_PIPELINE_COMPILE_REQUIRED)
    DHR_VK_RESULT_CASE(VK_ERROR_SURFACE_LOST_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
    DHR_VK_RESULT_CASE(VK_SUBOPTIMAL_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_OUT_OF_DATE_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DISPLAY_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
    DHR_VK_RESULT_CASE(VK_ERROR_INVALID_SHADER_NV)
    DHR_VK_RESULT_CASE(VK_ERROR_IMAGE_USAGE_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VIDEO_PICTURE_LAYOUT_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VIDEO_PROFILE_OPERATION_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VIDEO_PROFILE_FORMAT_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VIDEO_PROFILE_CODEC_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_VIDEO_STD_VERSION_NOT_SUPPORTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_INVALID_DRM_FORMAT_MODIFIER_PLANE_LAYOUT_EXT)
    DHR_VK_RESULT_CASE(VK_ERROR_NOT_PERMITTED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_FULL_SCREEN_EXCLUSIVE_MODE_LOST_EXT)
    DHR_VK_RESULT_CASE(VK_THREAD_IDLE_KHR)
    DHR_VK_RESULT_CASE(VK_THREAD_DONE_KHR)
    DHR_VK_RESULT_CASE(VK_OPERATION_DEFERRED_KHR)
    DHR_VK_RESULT_CASE(VK_OPERATION_NOT_DEFERRED_KHR)
    DHR_VK_RESULT_CASE(VK_ERROR_COMPRESSION_EXHAUSTED_EXT)
#undef DHR_VK_RESULT_CASE
    case VK_RESULT_MAX_ENUM:
      break;
  }
  return "VK_RESULT_UNKNOWN";
}

namespace {

// "vkCreateBuffer(device, &info, nullptr, &buffer)" -> "vkCreateBuffer(...)": the call name is what
// identifies the failure; the argument text only makes the one-line message long.
std::string short_expression(const char* expression) {
  const std::string_view text = expression != nullptr ? expression : "?";
  const size_t paren = text.find('(');
  if (paren == std::string_view::npos) return std::string(text);
  return std::string(text.substr(0, paren)) + "(...)";
}

const char* base_name(const char* path) {
  const char* slash = std::strrchr(path, '/');
  return slash != nullptr ? slash + 1 : path;
}

std::string format_message(VkResult result, const char* expression, const std::source_location& where) {
  char line[32];
  std::snprintf(line, sizeof line, "%u", static_cast<unsigned>(where.line()));
  std::string message = short_expression(expression);
  message += " failed: ";
  message += result_name(result);
  if (std::strcmp(result_name(result), "VK_RESULT_UNKNOWN") == 0) {
    message += " (" + std::to_string(static_cast<int>(result)) + ")";
  }
  message += " at ";
  message += base_name(where.file_name());
  message += ':';
  message += line;
  return message;
}

}  // namespace

VulkanError::VulkanError(VkResult result, const char* expression, std::source_location where)
    : std::runtime_error(format_message(result, expression, where)), result_(result) {}

void throw_vk_error(VkResult result, const char* expression, std::source_location where) {
  throw VulkanError(result, expression, where);
}

void log_vk_error(VkResult result, const char* expression, std::source_location where) {
  dhr::log::error("%s", format_message(result, expression, where).c_str());
}

}  // namespace dhr::vk
