// The OpenXR frame loop, one call per frame:
//   xrWaitFrame -> xrBeginFrame -> xrLocateViews -> per eye acquire/wait image -> render ->
//   release -> xrEndFrame with one projection layer (no layer when there is nothing to show).
// A thin coordinator: what is drawn into the images is the caller's render function.
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>

#include "xr/openxr_vulkan.hpp"
#include "xr/system.hpp"

namespace dhr::xr {

class Session;
class ReferenceSpaces;
class Swapchain;

struct EyeTarget {
  uint32_t eye = 0;  // 0 left, 1 right
  VkImage image = VK_NULL_HANDLE;  // in COLOR_ATTACHMENT_OPTIMAL layout; leave it so
  uint32_t image_index = 0;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{0, 0};
};

struct FrameState {
  uint64_t index = 0;  // frames begun so far, starting at 0
  XrTime predicted_display_time = 0;
  XrDuration predicted_period = 0;
  bool should_render = false;  // the runtime wants pixels (session VISIBLE or FOCUSED)
  bool views_valid = false;    // both eyes' position and orientation are valid
  XrViewStateFlags view_state_flags = 0;
  std::array<XrView, kEyeCount> views{};  // eye poses in the world space, with their FOVs
};

struct FrameLoopOptions {
  // xrWaitSwapchainImage timeout per attempt, and attempts before the frame fails. The image
  // is normally ready at once; the limit keeps a stuck runtime from hanging the client.
  XrDuration image_wait_timeout = 500'000'000;  // 0.5 s
  uint32_t image_wait_attempts = 4;
  // Where the head starts (xr/world_origin.hpp): at the first frame whose views are valid, the world space is
  // offset so that the head is located at this position and heading; later frames move from there with the head.
  std::optional<XrPosef> start_head;
};

// The views eye images were rendered with, when they are not the views located for this frame (a schedule
// that shows an older frame's pose). The projection layer must carry the rendered views, or the compositor
// reprojects the image from the wrong pose.
using RenderedViews = std::optional<std::array<XrView, kEyeCount>>;

// Draws into the acquired eye images (both acquired and waited) and says which views it drew them with
// (std::nullopt: the frame's located views). May throw; the frame is then left unfinished and the caller is
// expected to shut the session down.
using RenderFn = std::function<RenderedViews(const FrameState& frame, const std::array<EyeTarget, kEyeCount>& eyes)>;

// The projection layer's views: the rendered views where given, else the located ones.
std::array<XrView, kEyeCount> submitted_views(const FrameState& frame, const RenderedViews& rendered);

class FrameLoop {
 public:
  using Clock = std::chrono::steady_clock;

  FrameLoop(const Session& session, ReferenceSpaces& spaces,
            std::array<Swapchain*, kEyeCount> swapchains, XrEnvironmentBlendMode blend_mode,
            const FrameLoopOptions& options = {});

  // Runs one frame. Only call while the session is running. Returns XR_SUCCESS, or the first
  // failing XrResult (XR_TIMEOUT_EXPIRED when an image wait ran out of attempts).
  XrResult run_frame(const RenderFn& render, FrameState* out_frame = nullptr);

  uint64_t frames_begun() const { return frames_begun_; }
  uint64_t frames_ended() const { return frames_ended_; }
  uint64_t frames_presented() const { return frames_presented_; }  // ended with a layer
  // The region of each eye's swapchain image the client renders, from its top-left corner (the projection
  // layer's imageRect: the compositor scales it to the view; a render scale below 1). 0x0: the whole image.
  void set_image_extent(VkExtent2D extent) { image_extent_ = extent; }
  // Wall-clock times of the first and the last successful xrEndFrame.
  Clock::time_point first_end_time() const { return first_end_; }
  Clock::time_point last_end_time() const { return last_end_; }

 private:
  XrResult locate_views(FrameState& frame);
  XrResult acquire_images(std::array<EyeTarget, kEyeCount>& out_eyes);

  XrSession session_ = XR_NULL_HANDLE;
  ReferenceSpaces& spaces_;
  XrSpace world_ = XR_NULL_HANDLE;
  std::array<Swapchain*, kEyeCount> swapchains_{};
  XrEnvironmentBlendMode blend_mode_ = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  FrameLoopOptions options_;
  uint64_t frames_begun_ = 0;
  uint64_t frames_ended_ = 0;
  uint64_t frames_presented_ = 0;
  VkExtent2D image_extent_{0, 0};
  Clock::time_point first_end_{};
  Clock::time_point last_end_{};
};

}  // namespace dhr::xr
