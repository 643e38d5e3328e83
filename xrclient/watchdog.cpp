#include "watchdog.hpp"

#include <cstdio>
#include <cstdlib>

namespace dhr {

Watchdog::Watchdog(std::chrono::milliseconds limit, std::string message)
    : message_(std::move(message)) {
  thread_ = std::thread([this, limit] {
    std::unique_lock lock(mutex_);
    if (disarmed_cv_.wait_for(lock, limit, [this] { return disarmed_; })) return;
    std::fprintf(stderr, "error: %s\n", message_.c_str());
    std::fflush(stderr);
    std::_Exit(kExitCode);  // other threads may be stuck inside the runtime: no unwinding
  });
}

Watchdog::~Watchdog() {
  {
    std::lock_guard lock(mutex_);
    disarmed_ = true;
  }
  disarmed_cv_.notify_all();
  thread_.join();
}

}  // namespace dhr
