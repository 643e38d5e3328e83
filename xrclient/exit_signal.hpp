// SIGINT / SIGTERM -> a flag the frame loop polls, so the session can be shut down cleanly
// (xrRequestExitSession, STOPPING, xrEndSession) instead of the process dying mid-frame.
// The handler resets itself: a second signal kills the process the default way.
#pragma once

namespace dhr {

void install_exit_signal_handlers();
bool exit_signal_received();
int exit_signal_number();  // 0 when none arrived

}  // namespace dhr
