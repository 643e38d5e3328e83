// Last-resort wall-clock cap: if the guarded scope has not finished within the limit (a runtime
// call that never returns, e.g. xrWaitFrame), print one line and end the process.
#pragma once
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace dhr {

class Watchdog {
 public:
  static constexpr int kExitCode = 124;  // as timeout(1)

  Watchdog(std::chrono::milliseconds limit, std::string message);
  ~Watchdog();  // disarms
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable disarmed_cv_;
  bool disarmed_ = false;
  std::string message_;
  std::thread thread_;
};

}  // namespace dhr
