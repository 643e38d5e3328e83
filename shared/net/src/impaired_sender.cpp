#include "net/impaired_sender.hpp"

#include "net/clock.hpp"

#include <algorithm>
#include <chrono>

namespace dhr::net {
namespace {

struct Later {
  template <class T>
  bool operator()(const T& a, const T& b) const {
    return a.delivery_ns != b.delivery_ns ? a.delivery_ns > b.delivery_ns : a.order > b.order;
  }
};

std::chrono::steady_clock::time_point to_time_point(int64_t t_ns) {
  return std::chrono::steady_clock::time_point(
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::nanoseconds(t_ns)));
}

}  // namespace

ImpairedSender::ImpairedSender(DatagramSender& inner, const ImpairmentParams& params, size_t max_in_flight)
    : inner_(inner),
      params_(params),
      max_in_flight_(max_in_flight),
      passthrough_(!params.active()),
      model_(params) {
  if (!passthrough_) thread_ = std::thread([this] { run(); });
}

ImpairedSender::~ImpairedSender() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool ImpairedSender::send_to(std::span<const uint8_t> datagram, const PeerAddress& to) {
  const int64_t now = steady_now_ns();
  if (passthrough_) {
    {
      const std::lock_guard lock(mutex_);
      if (datagram.empty()) {
        ++rejected_;
        return false;
      }
      model_.next(now);  // keeps the statistics; an inactive model delivers at once
    }
    const bool accepted = inner_.send_to(datagram, to);
    const std::lock_guard lock(mutex_);
    ++(accepted ? forwarded_ : forward_refused_);
    return accepted;
  }

  std::unique_lock lock(mutex_);
  if (datagram.empty() || stopping_) {
    ++rejected_;
    return false;
  }
  if (heap_.size() + 2 > max_in_flight_) {
    ++dropped_overflow_;
    return false;
  }
  const ImpairmentDecision decision = model_.next(now);
  const int64_t earliest_before = heap_.empty() ? INT64_MAX : heap_.front().delivery_ns;
  for (uint8_t copy = 0; copy < decision.delivery_count; ++copy) {
    heap_.push_back(Held{decision.delivery_ns[copy], order_++, to, {datagram.begin(), datagram.end()}});
    std::push_heap(heap_.begin(), heap_.end(), Later());
  }
  const bool wake = !heap_.empty() && heap_.front().delivery_ns < earliest_before;
  lock.unlock();
  if (wake) wake_.notify_one();
  return true;  // lost datagrams count as sent: the loss happens "on the wire"
}

void ImpairedSender::run() {
  std::vector<Held> due;
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (heap_.empty()) {
      idle_.notify_all();
      wake_.wait(lock);
      continue;
    }
    const int64_t next = heap_.front().delivery_ns;
    if (next > steady_now_ns()) {
      wake_.wait_until(lock, to_time_point(next));
      continue;
    }
    const int64_t now = steady_now_ns();
    while (!heap_.empty() && heap_.front().delivery_ns <= now) {
      std::pop_heap(heap_.begin(), heap_.end(), Later());
      due.push_back(std::move(heap_.back()));
      heap_.pop_back();
    }
    forwarding_ = due.size();
    lock.unlock();
    uint64_t accepted = 0;
    for (const Held& held : due) accepted += inner_.send_to(held.bytes, held.to) ? 1 : 0;
    lock.lock();
    forwarded_ += accepted;
    forward_refused_ += due.size() - accepted;
    forwarding_ = 0;
    due.clear();
  }
  heap_.clear();  // discarded on shutdown
  idle_.notify_all();
}

bool ImpairedSender::wait_idle(int64_t timeout_ns) {
  int64_t deadline = 0;
  if (__builtin_add_overflow(steady_now_ns(), std::max<int64_t>(timeout_ns, 0), &deadline)) deadline = INT64_MAX;
  std::unique_lock lock(mutex_);
  return idle_.wait_until(lock, to_time_point(deadline),
                          [this] { return heap_.empty() && forwarding_ == 0; });
}

ImpairedSenderStats ImpairedSender::stats() const {
  const std::lock_guard lock(mutex_);
  ImpairedSenderStats stats;
  stats.model = model_.stats();
  stats.forwarded = forwarded_;
  stats.forward_refused = forward_refused_;
  stats.dropped_overflow = dropped_overflow_;
  stats.rejected = rejected_;
  stats.in_flight = heap_.size() + forwarding_;
  return stats;
}

}  // namespace dhr::net
