#include "exit_signal.hpp"

#include <csignal>

namespace dhr {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_exit_signal(int signal_number) { g_signal = signal_number; }

}  // namespace

void install_exit_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_exit_signal;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: the runtime's threads must not see EINTR; SA_RESETHAND: a second signal kills.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool exit_signal_received() { return g_signal != 0; }

int exit_signal_number() { return static_cast<int>(g_signal); }

}  // namespace dhr
