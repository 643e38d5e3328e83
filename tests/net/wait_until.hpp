// Polling helper for loopback tests: waits for a condition with a generous timeout. Tests assert the
// condition's outcome, never how long it took.
#pragma once
#include <chrono>
#include <thread>

namespace dhr::net::test {

template <class Predicate>
bool wait_until(Predicate predicate, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return predicate();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace dhr::net::test
