// The OpenXR session's outer loop, shared by --smoke and the main client: poll events, run frames while the
// session runs, ask for exit when enough frames were presented, a signal arrived, the wall-clock cap passed
// or the caller says stop, and walk the session down (bounded) before returning.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "xr/frame_loop.hpp"

namespace dhr::xr {
class Headset;
}

namespace dhr {

struct SessionLoopOptions {
  uint64_t frames = 300;    // frames presented (with a projection layer) before asking to exit
  double timeout_s = 60.0;  // wall-clock cap of the frame phase
  const char* log_name = "xr";
};

struct SessionLoopResult {
  std::string exit = "error";  // clean | timeout | loss_pending | instance_lost | error | stopped
  bool failed = false;
  bool timed_out = false;
  int signal = 0;
};

// `after_frame` (optional) sees each frame's state after xrEndFrame; returning false asks the session to
// exit (exit "stopped" unless something else went wrong first). Render exceptions propagate.
SessionLoopResult run_session_loop(xr::Headset& headset, const SessionLoopOptions& options,
                                   const xr::RenderFn& render,
                                   const std::function<bool(const xr::FrameState&)>& after_frame = {});

}  // namespace dhr
