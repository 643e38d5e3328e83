// OpenXR with its Vulkan platform types (XR_KHR_vulkan_enable2). Include this instead of
// <openxr/openxr_platform.h> so the platform macro and the include order are right everywhere.
#pragma once
#include <vulkan/vulkan.h>

#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN
#endif
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
