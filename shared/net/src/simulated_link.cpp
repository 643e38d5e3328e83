#include "net/simulated_link.hpp"

#include <algorithm>

namespace dhr::net {

SimulatedLink::SimulatedLink(const ImpairmentParams& params, const Clock& clock, size_t max_in_flight)
    : clock_(clock), max_in_flight_(max_in_flight), model_(params) {}

bool SimulatedLink::send_to(std::span<const uint8_t> datagram, const PeerAddress& to) {
  return send_at(datagram, to, clock_.now_ns());
}

bool SimulatedLink::send_at(std::span<const uint8_t> datagram, const PeerAddress& to, int64_t send_time_ns,
                            ImpairmentDecision* out_decision) {
  const std::lock_guard lock(mutex_);
  if (datagram.empty()) {
    ++rejected_;
    return false;
  }
  // Check the bound before consulting the model, so a refused datagram does not advance the schedule.
  if (queue_.size() + 2 > max_in_flight_) {
    ++dropped_overflow_;
    return false;
  }
  const ImpairmentDecision decision = model_.next(send_time_ns);
  if (out_decision) *out_decision = decision;
  for (uint8_t copy = 0; copy < decision.delivery_count; ++copy) {
    Pending pending;
    pending.delivery_ns = decision.delivery_ns[copy];
    pending.order = order_++;
    pending.sequence = decision.sequence;
    pending.send_ns = send_time_ns;
    pending.duplicate = copy == 1;
    pending.to = to;
    pending.bytes.assign(datagram.begin(), datagram.end());
    queue_.push_back(std::move(pending));
    std::push_heap(queue_.begin(), queue_.end(), Later());
  }
  return true;
}

size_t SimulatedLink::deliver_due(const DeliverySink& sink) { return deliver_until(clock_.now_ns(), sink); }

size_t SimulatedLink::deliver_until(int64_t now_ns, const DeliverySink& sink) {
  std::vector<Pending> due;
  {
    const std::lock_guard lock(mutex_);
    while (!queue_.empty() && queue_.front().delivery_ns <= now_ns) {
      std::pop_heap(queue_.begin(), queue_.end(), Later());
      due.push_back(std::move(queue_.back()));
      queue_.pop_back();
    }
    delivered_ += due.size();
  }
  for (const Pending& pending : due) {
    if (sink) {
      sink(SimulatedDelivery{pending.bytes, pending.to, pending.sequence, pending.send_ns, pending.delivery_ns,
                             pending.duplicate});
    }
  }
  return due.size();
}

std::optional<int64_t> SimulatedLink::next_delivery_ns() const {
  const std::lock_guard lock(mutex_);
  if (queue_.empty()) return std::nullopt;
  return queue_.front().delivery_ns;
}

size_t SimulatedLink::in_flight() const {
  const std::lock_guard lock(mutex_);
  return queue_.size();
}

SimulatedLinkStats SimulatedLink::stats() const {
  const std::lock_guard lock(mutex_);
  SimulatedLinkStats stats;
  stats.model = model_.stats();
  stats.delivered = delivered_;
  stats.dropped_overflow = dropped_overflow_;
  stats.rejected = rejected_;
  stats.in_flight = queue_.size();
  return stats;
}

}  // namespace dhr::net
