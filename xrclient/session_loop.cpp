#include "session_loop.hpp"

#include <chrono>
#include <thread>

#include "log/log.hpp"
#include "exit_signal.hpp"
#include "xr/headset.hpp"
#include "xr/xr_check.hpp"

namespace dhr {

namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

// How long the runtime gets to walk the session down to EXITING once asked.
constexpr Seconds kExitGrace{5.0};

}  // namespace

SessionLoopResult run_session_loop(xr::Headset& headset, const SessionLoopOptions& options,
                                   const xr::RenderFn& render,
                                   const std::function<bool(const xr::FrameState&)>& after_frame) {
  xr::Session& session = headset.session();
  xr::FrameLoop& loop = headset.frame_loop();
  const Seconds frame_phase_cap{options.timeout_s};
  const char* name = options.log_name;
  SessionLoopResult result;
  bool stopped = false;

  const Clock::time_point start = Clock::now();
  Clock::time_point exit_requested_at{};
  auto request_exit = [&](const char* why) {
    if (session.exit_requested()) return;
    dhr::log::info("%s: requesting session exit (%s)", name, why);
    exit_requested_at = Clock::now();
    session.request_exit();
  };

  while (!session.done()) {
    if (XR_FAILED(session.poll_events())) {
      result.failed = true;
      request_exit("event handling failed");
    }
    if (session.done()) break;
    if (exit_signal_received()) {
      result.signal = exit_signal_number();
      request_exit("signal");
    }
    const Clock::time_point now = Clock::now();
    if (!session.exit_requested() && now - start > frame_phase_cap) {
      dhr::log::error("%s: wall-clock cap of %.0f s reached after %llu frames", name, options.timeout_s,
                      static_cast<unsigned long long>(loop.frames_ended()));
      result.timed_out = true;
      request_exit("wall-clock cap");
    }
    // Count frames that really carried pixels: the first ones may come before VISIBLE.
    if (!session.exit_requested() && loop.frames_presented() >= options.frames) request_exit("frame count reached");
    if (session.exit_requested() && now - exit_requested_at > kExitGrace) {
      dhr::log::error("%s: the runtime did not end the session within %.0f s", name, kExitGrace.count());
      result.timed_out = true;
      break;
    }
    // After a failed frame keep polling (the exit walk may still complete) but stop rendering.
    if (session.running() && !result.failed) {
      xr::FrameState frame;
      const XrResult r = loop.run_frame(render, &frame);
      if (XR_FAILED(r) || r == XR_TIMEOUT_EXPIRED) {
        dhr::log::error("%s: frame %llu failed: %s", name, static_cast<unsigned long long>(loop.frames_begun()),
                        xr::result_name(r).c_str());
        result.failed = true;
        request_exit("frame failed");
        continue;
      }
      if (after_frame && !after_frame(frame) && !stopped) {
        stopped = true;
        request_exit("stopped by the application");
      }
    } else {
      // Waiting for READY or for the exit walk: the runtime drives this, poll at a gentle rate.
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  if (result.failed) {
    result.exit = "error";
  } else if (result.timed_out) {
    result.exit = "timeout";
  } else if (stopped) {
    result.exit = "stopped";
  } else if (session.end() == xr::SessionEnd::kExited) {
    result.exit = "clean";
  } else {
    result.exit = xr::session_end_name(session.end());
  }
  return result;
}

}  // namespace dhr
