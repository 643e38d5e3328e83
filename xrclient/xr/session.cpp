#include "xr/session.hpp"

#include <openxr/openxr_reflection.h>

#include <algorithm>

#include "log/log.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_struct.hpp"

namespace dhr::xr {

std::string session_state_name(XrSessionState state) {
  switch (state) {
#define DHR_XR_STATE_CASE(name, value) \
  case name:                           \
    return std::string(#name).substr(sizeof("XR_SESSION_STATE_") - 1);
    XR_LIST_ENUM_XrSessionState(DHR_XR_STATE_CASE)
#undef DHR_XR_STATE_CASE
    default:
      break;
  }
  return "STATE_" + std::to_string(static_cast<int>(state));
}

const char* session_end_name(SessionEnd end) {
  switch (end) {
    case SessionEnd::kNone: return "none";
    case SessionEnd::kExited: return "exited";
    case SessionEnd::kLossPending: return "loss_pending";
    case SessionEnd::kInstanceLost: return "instance_lost";
  }
  return "unknown";
}

Session::Session(XrInstance instance, XrSystemId system, const XrGraphicsBindingVulkan2KHR& binding)
    : instance_(instance) {
  auto create_info = make_xr<XrSessionCreateInfo>(XR_TYPE_SESSION_CREATE_INFO);
  create_info.next = &binding;
  create_info.systemId = system;
  const XrResult result = xrCreateSession(instance_, &create_info, &session_);
  if (XR_FAILED(result)) {
    session_ = XR_NULL_HANDLE;
    throw SessionRefused("the OpenXR runtime refused the session: xrCreateSession returned " +
                         result_name(result));
  }
}

Session::~Session() {
  if (session_ == XR_NULL_HANDLE) return;
  // Normally ended on STOPPING; this covers unwinding after an error mid-session.
  if (running_) xrEndSession(session_);
  xrDestroySession(session_);
}

bool Session::reached(XrSessionState state) const {
  return std::find(states_seen_.begin(), states_seen_.end(), state) != states_seen_.end();
}

void Session::request_exit() {
  if (exit_requested_ || done()) return;
  exit_requested_ = true;
  if (!running_) {
    // Nothing was begun (or it already ended): the session can be destroyed right away.
    end_ = SessionEnd::kExited;
    return;
  }
  const XrResult result = xrRequestExitSession(session_);
  if (XR_FAILED(result)) {
    log_xr_error(result, "xrRequestExitSession(session_)");
    end_ = SessionEnd::kExited;
  }
}

XrResult Session::poll_events() {
  failure_ = XR_SUCCESS;
  for (;;) {
    auto event = make_xr<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    const XrResult result = xrPollEvent(instance_, &event);
    if (result == XR_EVENT_UNAVAILABLE) break;
    DHR_XR_TRY(result);
    switch (event.type) {
      case XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED: {
        const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
        if (changed.session == session_) on_state_changed(changed.state);
        break;
      }
      case XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING:
        dhr::log::warn("openxr: instance loss pending");
        end_ = SessionEnd::kInstanceLost;
        break;
      case XR_TYPE_EVENT_DATA_EVENTS_LOST: {
        const auto& lost = reinterpret_cast<const XrEventDataEventsLost&>(event);
        dhr::log::warn("openxr: the runtime dropped %u events", lost.lostEventCount);
        break;
      }
      case XR_TYPE_EVENT_DATA_REFERENCE_SPACE_CHANGE_PENDING:
        dhr::log::info("openxr: reference space change pending");
        break;
      default:
        dhr::log::debug("openxr: event type %d ignored", static_cast<int>(event.type));
        break;
    }
  }
  return failure_;
}

void Session::on_state_changed(XrSessionState state) {
  dhr::log::info("openxr: session state %s -> %s", session_state_name(state_).c_str(),
                 session_state_name(state).c_str());
  state_ = state;
  states_seen_.push_back(state);
  switch (state) {
    case XR_SESSION_STATE_READY: {
      if (exit_requested_) {
        end_ = SessionEnd::kExited;  // asked to leave before the session started
        break;
      }
      auto begin_info = make_xr<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
      begin_info.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
      const XrResult result = xrBeginSession(session_, &begin_info);
      if (XR_FAILED(result)) {
        log_xr_error(result, "xrBeginSession(session_, &begin_info)");
        if (failure_ == XR_SUCCESS) failure_ = result;
        break;
      }
      running_ = true;
      break;
    }
    case XR_SESSION_STATE_STOPPING: {
      running_ = false;
      const XrResult result = xrEndSession(session_);
      if (XR_FAILED(result)) {
        log_xr_error(result, "xrEndSession(session_)");
        if (failure_ == XR_SUCCESS) failure_ = result;
      }
      break;
    }
    case XR_SESSION_STATE_EXITING:
      end_ = SessionEnd::kExited;
      break;
    case XR_SESSION_STATE_LOSS_PENDING:
      running_ = false;  // the session is unusable; xrEndSession would fail
      end_ = SessionEnd::kLossPending;
      break;
    default:
      break;
  }
}

}  // namespace dhr::xr
