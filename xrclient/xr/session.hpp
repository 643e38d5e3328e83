// The OpenXR session and its lifecycle state machine:
//   IDLE -> READY: xrBeginSession (running) -> SYNCHRONIZED -> VISIBLE -> FOCUSED
//   STOPPING: xrEndSession (not running) -> IDLE -> EXITING: done
//   LOSS_PENDING or instance loss: done (the session is gone, no end call)
// request_exit() asks the runtime to walk the session down to EXITING (xrRequestExitSession).
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "xr/openxr_vulkan.hpp"

namespace dhr::xr {

// The runtime would not create a session (e.g. graphics device not the headset's).
class SessionRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class SessionEnd {
  kNone,          // still alive
  kExited,        // reached EXITING (after our request or the runtime's): a clean end
  kLossPending,   // LOSS_PENDING: the runtime lost the session (headset unplugged, ...)
  kInstanceLost,  // INSTANCE_LOSS_PENDING: the runtime is going away
};

// "FOCUSED" etc. (the enum name without the XR_SESSION_STATE_ prefix).
std::string session_state_name(XrSessionState state);
const char* session_end_name(SessionEnd end);

class Session {
 public:
  // Throws SessionRefused with the runtime's XrResult name when xrCreateSession fails.
  Session(XrInstance instance, XrSystemId system, const XrGraphicsBindingVulkan2KHR& binding);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  XrSession handle() const { return session_; }

  // Drains the event queue and acts on state changes (begin on READY, end on STOPPING).
  // Returns the first failing XrResult of a begin/end/poll call, XR_SUCCESS otherwise.
  XrResult poll_events();

  // Asks the runtime to end the session; without a running session there is nothing to walk
  // down, so the session is done at once. Idempotent.
  void request_exit();

  bool running() const { return running_; }  // between xrBeginSession and xrEndSession
  bool exit_requested() const { return exit_requested_; }
  // True once the application must stop its loop and destroy the session.
  bool done() const { return end_ != SessionEnd::kNone; }
  SessionEnd end() const { return end_; }
  XrSessionState state() const { return state_; }
  // Every state the session entered, in order (starting with the first event, usually IDLE).
  const std::vector<XrSessionState>& states_seen() const { return states_seen_; }
  bool reached(XrSessionState state) const;

 private:
  void on_state_changed(XrSessionState state);

  XrInstance instance_ = XR_NULL_HANDLE;
  XrSession session_ = XR_NULL_HANDLE;
  XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
  std::vector<XrSessionState> states_seen_;
  bool running_ = false;
  bool exit_requested_ = false;
  SessionEnd end_ = SessionEnd::kNone;
  XrResult failure_ = XR_SUCCESS;  // first failure of a call made while handling an event
};

}  // namespace dhr::xr
