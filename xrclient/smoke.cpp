#include "smoke.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <thread>

#include "core/log.hpp"
#include "exit_signal.hpp"
#include "watchdog.hpp"
#include "xr/headset.hpp"
#include "xr/xr_check.hpp"

namespace dhr {

namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

// How long the runtime gets to walk the session down to EXITING once asked.
constexpr Seconds kExitGrace{5.0};
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

VkImageMemoryBarrier layout_barrier(VkImage image, VkImageLayout from, VkImageLayout to,
                                    VkAccessFlags src_access, VkAccessFlags dst_access) {
  VkImageMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  return barrier;
}

// Swapchain images are handed over in COLOR_ATTACHMENT_OPTIMAL and must be returned so.
void record_clear(VkCommandBuffer cmd, VkImage image, const VkClearColorValue& colour) {
  const VkImageMemoryBarrier to_transfer = layout_barrier(
      image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &to_transfer);
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &colour, 1, &range);
  const VkImageMemoryBarrier to_attachment = layout_barrier(
      image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
      VK_ACCESS_TRANSFER_WRITE_BIT,
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr, 1,
                       &to_attachment);
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
  Clock::time_point exit_requested_at{};
  bool timed_out = false;
  bool failed = false;
  auto request_exit = [&](const char* why) {
    if (session.exit_requested()) return;
    dhr::log::info("smoke: requesting session exit (%s)", why);
    exit_requested_at = Clock::now();
    session.request_exit();
  };

  const xr::RenderFn clear_eyes = [&](const xr::FrameState&,
                                      const std::array<xr::EyeTarget, xr::kEyeCount>& eyes) {
    const double seconds = Seconds(Clock::now() - start).count();
    vulkan.submit_and_wait([&](VkCommandBuffer cmd) {
      for (const xr::EyeTarget& eye : eyes) record_clear(cmd, eye.image, eye_colour(eye.eye, seconds));
    });
  };

  while (!session.done()) {
    if (XR_FAILED(session.poll_events())) {
      failed = true;
      request_exit("event handling failed");
    }
    if (session.done()) break;
    if (exit_signal_received()) {
      report.signal = exit_signal_number();
      request_exit("signal");
    }
    const Clock::time_point now = Clock::now();
    if (!session.exit_requested() && now - start > frame_phase_cap) {
      dhr::log::error("smoke: wall-clock cap of %.0f s reached after %llu frames",
                      options.timeout_s, static_cast<unsigned long long>(loop.frames_ended()));
      timed_out = true;
      request_exit("wall-clock cap");
    }
    // Count frames that really carried pixels: the first ones may come before VISIBLE.
    if (!session.exit_requested() && loop.frames_presented() >= options.frames) {
      request_exit("frame count reached");
    }
    if (session.exit_requested() && now - exit_requested_at > kExitGrace) {
      dhr::log::error("smoke: the runtime did not end the session within %.0f s",
                      kExitGrace.count());
      timed_out = true;
      break;
    }
    // After a failed frame keep polling (the exit walk may still complete) but stop rendering.
    if (session.running() && !failed) {
      xr::FrameState frame;
      const XrResult result = loop.run_frame(clear_eyes, &frame);
      if (XR_FAILED(result) || result == XR_TIMEOUT_EXPIRED) {
        dhr::log::error("smoke: frame %llu failed: %s",
                        static_cast<unsigned long long>(loop.frames_begun()),
                        xr::result_name(result).c_str());
        failed = true;
        request_exit("frame failed");
        continue;
      }
      if (frame.views_valid) report.poses.add(frame.views);
    } else {
      // Waiting for READY or for the exit walk: the runtime drives this, poll at a gentle rate.
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  report.frames = loop.frames_ended();
  report.frames_presented = loop.frames_presented();
  const double span = Seconds(loop.last_end_time() - loop.first_end_time()).count();
  report.fps = report.frames > 1 && span > 0.0 ? static_cast<double>(report.frames - 1) / span : 0.0;
  report.reached_focused = session.reached(XR_SESSION_STATE_FOCUSED);
  for (XrSessionState state : session.states_seen()) {
    report.states.push_back(xr::session_state_name(state));
  }
  if (failed) {
    report.exit = "error";
  } else if (timed_out) {
    report.exit = "timeout";
  } else if (session.end() == xr::SessionEnd::kExited) {
    report.exit = "clean";
  } else {
    report.exit = xr::session_end_name(session.end());
  }
  return report;
}

}  // namespace dhr
