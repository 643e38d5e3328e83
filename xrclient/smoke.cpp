#include "smoke.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "log/log.hpp"
#include "session_loop.hpp"
#include "vk/barriers.hpp"
#include "watchdog.hpp"
#include "xr/headset.hpp"
#include "xr/xr_check.hpp"

namespace dhr {

namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

// Margin of the hard cap beyond the frame-phase cap: setup, exit walk and teardown.
constexpr Seconds kHardCapMargin{30.0};

// A slowly cycling colour, phase-shifted per eye so each eye is visibly different.
VkClearColorValue eye_colour(uint32_t eye, double seconds) {
  constexpr double kCyclesPerSecond = 0.25;
  const double phase = kCyclesPerSecond * seconds + (eye == 0 ? 0.0 : 0.5);
  VkClearColorValue colour{};
  for (int channel = 0; channel < 3; ++channel) {
    const double angle = 2.0 * std::numbers::pi * (phase + channel / 3.0);
    colour.float32[channel] = static_cast<float>(0.5 + 0.5 * std::sin(angle));
  }
  colour.float32[3] = 1.0f;
  return colour;
}

// Swapchain images are handed over in COLOR_ATTACHMENT_OPTIMAL and must be returned so.
void record_clear(VkCommandBuffer cmd, VkImage image, const VkClearColorValue& colour) {
  vk::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT);
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &colour, 1, &range);
  vk::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

void fill_static_fields(const xr::Headset& headset, SmokeReport& report) {
  report.runtime = headset.instance().runtime().describe();
  report.system = headset.system().name;
  report.world_space = xr::reference_space_name(headset.spaces().world_type());
  report.vk_device = headset.vulkan().info().name;
  for (uint32_t eye = 0; eye < xr::kEyeCount; ++eye) {
    report.eye_size[eye] = {headset.swapchain(eye).desc().width,
                            headset.swapchain(eye).desc().height};
  }
  report.swapchain_format = static_cast<int64_t>(headset.swapchain(0).desc().format);
}

}  // namespace

SmokeReport run_smoke(const SmokeOptions& options) {
  const Seconds frame_phase_cap{options.timeout_s};
  Watchdog watchdog(std::chrono::duration_cast<std::chrono::milliseconds>(frame_phase_cap + kHardCapMargin),
                    "smoke run exceeded its wall-clock cap (a runtime call did not return)");

  xr::HeadsetOptions headset_options;
  headset_options.instance.app_name = "dhr-xrclient-smoke";
  headset_options.vulkan.app_name = "dhr-xrclient-smoke";
  headset_options.vulkan.device = options.device;
  headset_options.color_encoding = options.color_encoding;
  const std::unique_ptr<xr::Headset> headset = xr::Headset::open(headset_options);
  xr::Session& session = headset->session();
  xr::FrameLoop& loop = headset->frame_loop();
  const vk::Context& vulkan = headset->vulkan();

  SmokeReport report;
  fill_static_fields(*headset, report);

  const Clock::time_point start = Clock::now();
  const xr::RenderFn clear_eyes = [&](const xr::FrameState&,
                                      const std::array<xr::EyeTarget, xr::kEyeCount>& eyes) -> xr::RenderedViews {
    const double seconds = Seconds(Clock::now() - start).count();
    vulkan.submit_and_wait([&](VkCommandBuffer cmd) {
      for (const xr::EyeTarget& eye : eyes) record_clear(cmd, eye.image, eye_colour(eye.eye, seconds));
    });
    return std::nullopt;  // drawn for the located views
  };
  SessionLoopOptions loop_options;
  loop_options.frames = options.frames;
  loop_options.timeout_s = options.timeout_s;
  loop_options.log_name = "smoke";
  const SessionLoopResult result =
      run_session_loop(*headset, loop_options, clear_eyes, [&](const xr::FrameState& frame) {
        if (frame.views_valid) report.poses.add(frame.views);
        return true;
      });
  report.signal = result.signal;

  report.frames = loop.frames_ended();
  report.frames_presented = loop.frames_presented();
  const double span = Seconds(loop.last_end_time() - loop.first_end_time()).count();
  report.fps = report.frames > 1 && span > 0.0 ? static_cast<double>(report.frames - 1) / span : 0.0;
  report.reached_focused = session.reached(XR_SESSION_STATE_FOCUSED);
  for (XrSessionState state : session.states_seen()) {
    report.states.push_back(xr::session_state_name(state));
  }
  report.exit = result.exit;
  return report;
}

}  // namespace dhr
