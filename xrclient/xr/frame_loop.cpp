#include "xr/frame_loop.hpp"

#include "log/log.hpp"
#include "xr/session.hpp"
#include "xr/spaces.hpp"
#include "xr/swapchain.hpp"
#include "xr/world_origin.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

FrameLoop::FrameLoop(const Session& session, ReferenceSpaces& spaces,
                     std::array<Swapchain*, kEyeCount> swapchains,
                     XrEnvironmentBlendMode blend_mode, const FrameLoopOptions& options)
    : session_(session.handle()),
      spaces_(spaces),
      world_(spaces.world()),
      swapchains_(swapchains),
      blend_mode_(blend_mode),
      options_(options) {}

std::array<XrView, kEyeCount> submitted_views(const FrameState& frame, const RenderedViews& rendered) {
  return rendered ? *rendered : frame.views;
}

XrResult FrameLoop::locate_views(FrameState& frame) {
  auto locate_info = make_xr<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
  locate_info.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  locate_info.displayTime = frame.predicted_display_time;
  locate_info.space = world_;
  auto view_state = make_xr<XrViewState>(XR_TYPE_VIEW_STATE);
  for (XrView& view : frame.views) view = make_xr<XrView>(XR_TYPE_VIEW);
  uint32_t count = 0;
  DHR_XR_TRY(xrLocateViews(session_, &locate_info, &view_state, kEyeCount, &count,
                           frame.views.data()));
  constexpr XrViewStateFlags kValid =
      XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
  frame.view_state_flags = view_state.viewStateFlags;
  frame.views_valid = count == kEyeCount && (view_state.viewStateFlags & kValid) == kValid;
  if (frame.views_valid && options_.start_head) {
    // The first valid views: move the world so that the head starts where asked, and locate again in it. A pose
    // that is not finite (a runtime's bad sample) leaves the offset for the next frame.
    const XrPosef offset =
        world_offset_for_start(head_of_views(frame.views[0].pose, frame.views[1].pose), *options_.start_head);
    if (!finite_pose(offset)) return XR_SUCCESS;
    spaces_.offset_world(offset);
    world_ = spaces_.world();
    options_.start_head.reset();
    return locate_views(frame);
  }
  return XR_SUCCESS;
}

XrResult FrameLoop::acquire_images(std::array<EyeTarget, kEyeCount>& out_eyes) {
  for (uint32_t eye = 0; eye < kEyeCount; ++eye) {
    Swapchain& swapchain = *swapchains_[eye];
    EyeTarget& target = out_eyes[eye];
    DHR_XR_TRY(swapchain.acquire(&target.image_index));
    XrResult wait_result = XR_TIMEOUT_EXPIRED;
    for (uint32_t attempt = 0; attempt < options_.image_wait_attempts; ++attempt) {
      wait_result = swapchain.wait(options_.image_wait_timeout);
      if (wait_result != XR_TIMEOUT_EXPIRED) break;
      dhr::log::warn("openxr: eye %u swapchain image not ready after %.1f s (attempt %u)", eye,
                     static_cast<double>(options_.image_wait_timeout) * 1e-9, attempt + 1);
    }
    if (wait_result != XR_SUCCESS) return wait_result;
    target.eye = eye;
    target.image = swapchain.images()[target.image_index];
    target.format = swapchain.desc().format;
    target.extent = {swapchain.desc().width, swapchain.desc().height};
  }
  return XR_SUCCESS;
}

XrResult FrameLoop::run_frame(const RenderFn& render, FrameState* out_frame) {
  FrameState frame;
  auto wait_info = make_xr<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  auto frame_state = make_xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  DHR_XR_TRY(xrWaitFrame(session_, &wait_info, &frame_state));
  frame.index = frames_begun_;
  frame.predicted_display_time = frame_state.predictedDisplayTime;
  frame.predicted_period = frame_state.predictedDisplayPeriod;
  frame.should_render = frame_state.shouldRender == XR_TRUE;

  auto begin_info = make_xr<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  // XR_FRAME_DISCARDED (a success code) only says an earlier frame was never ended.
  DHR_XR_TRY(xrBeginFrame(session_, &begin_info));
  ++frames_begun_;

  DHR_XR_TRY(locate_views(frame));

  std::array<XrCompositionLayerProjectionView, kEyeCount> projection_views{};
  auto projection = make_xr<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
  const bool present = frame.should_render && frame.views_valid;
  if (present) {
    std::array<EyeTarget, kEyeCount> eyes{};
    DHR_XR_TRY(acquire_images(eyes));
    const std::array<XrView, kEyeCount> submitted = submitted_views(frame, render(frame, eyes));
    for (uint32_t eye = 0; eye < kEyeCount; ++eye) {
      DHR_XR_TRY(swapchains_[eye]->release());
      XrCompositionLayerProjectionView& view = projection_views[eye];
      view = make_xr<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW);
      view.pose = submitted[eye].pose;
      view.fov = submitted[eye].fov;
      view.subImage.swapchain = swapchains_[eye]->handle();
      view.subImage.imageRect.offset = {0, 0};
      const bool part = image_extent_.width > 0 && image_extent_.height > 0;
      view.subImage.imageRect.extent = {
          static_cast<int32_t>(part ? std::min(image_extent_.width, eyes[eye].extent.width) : eyes[eye].extent.width),
          static_cast<int32_t>(part ? std::min(image_extent_.height, eyes[eye].extent.height) : eyes[eye].extent.height)};
      view.subImage.imageArrayIndex = 0;
    }
    projection.space = world_;
    projection.viewCount = kEyeCount;
    projection.views = projection_views.data();
  }
  const XrCompositionLayerBaseHeader* layers[] = {
      reinterpret_cast<const XrCompositionLayerBaseHeader*>(&projection)};

  auto end_info = make_xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end_info.displayTime = frame.predicted_display_time;
  end_info.environmentBlendMode = blend_mode_;
  end_info.layerCount = present ? 1 : 0;
  end_info.layers = present ? layers : nullptr;
  DHR_XR_TRY(xrEndFrame(session_, &end_info));

  const Clock::time_point now = Clock::now();
  if (frames_ended_ == 0) first_end_ = now;
  last_end_ = now;
  ++frames_ended_;
  if (present) ++frames_presented_;
  if (out_frame != nullptr) *out_frame = frame;
  return XR_SUCCESS;
}

}  // namespace dhr::xr
