// SimulatedLink: an in-process one-way link driven by a clock (usually a VirtualClock): datagrams go in
// with send_to(), the ImpairmentModel decides when (and whether, and how often) each comes out, and
// deliver_due() releases everything whose delivery time has passed, earliest first (equal times in
// send order). Used by tests and dhr-eval so the whole pipeline runs deterministically with no sockets.
// Implements DatagramSender, so code written against a socket can send into it unchanged.
#pragma once
#include "net/clock.hpp"
#include "net/impairment.hpp"
#include "net/udp_socket.hpp"

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

namespace dhr::net {

struct SimulatedDelivery {
  std::span<const uint8_t> bytes;  // valid during the sink call only
  PeerAddress to;                  // as given to send_to
  uint64_t sequence = 0;           // the datagram's index in send order (a duplicate repeats it)
  int64_t send_time_ns = 0;
  int64_t delivery_time_ns = 0;
  bool duplicate = false;          // the second copy of a duplicated datagram
};

using DeliverySink = std::function<void(const SimulatedDelivery& delivery)>;

struct SimulatedLinkStats {
  ImpairmentStats model;          // what the impairment model decided
  uint64_t delivered = 0;         // copies released to a sink
  uint64_t dropped_overflow = 0;  // refused because max_in_flight copies were queued
  uint64_t rejected = 0;          // empty datagrams refused
  uint64_t in_flight = 0;         // copies queued now
};

// Thread-safe (one mutex); sinks run without the lock held, so a sink may send into any link. Deliver
// from one thread at a time, or copies released by concurrent calls may reach their sinks out of order.
class SimulatedLink final : public DatagramSender {
 public:
  // `clock` must outlive the link. Throws std::invalid_argument when the params are invalid.
  SimulatedLink(const ImpairmentParams& params, const Clock& clock, size_t max_in_flight = 65536);

  bool send_to(std::span<const uint8_t> datagram, const PeerAddress& to) override;  // at clock.now_ns()
  bool send(std::span<const uint8_t> datagram) { return send_to(datagram, PeerAddress()); }
  // Explicit send time (send times should not go back); returns false when refused.
  bool send_at(std::span<const uint8_t> datagram, const PeerAddress& to, int64_t send_time_ns,
               ImpairmentDecision* out_decision = nullptr);

  size_t deliver_due(const DeliverySink& sink);  // everything due at clock.now_ns(); returns the count
  size_t deliver_until(int64_t now_ns, const DeliverySink& sink);

  std::optional<int64_t> next_delivery_ns() const;  // nullopt when nothing is in flight
  size_t in_flight() const;
  SimulatedLinkStats stats() const;

 private:
  struct Pending {
    int64_t delivery_ns = 0;
    uint64_t order = 0;  // insertion counter: FIFO among equal delivery times
    uint64_t sequence = 0;
    int64_t send_ns = 0;
    bool duplicate = false;
    PeerAddress to;
    std::vector<uint8_t> bytes;
  };
  struct Later {
    bool operator()(const Pending& a, const Pending& b) const {
      return a.delivery_ns != b.delivery_ns ? a.delivery_ns > b.delivery_ns : a.order > b.order;
    }
  };

  const Clock& clock_;
  const size_t max_in_flight_;
  mutable std::mutex mutex_;
  ImpairmentModel model_;
  std::vector<Pending> queue_;  // min-heap on (delivery_ns, order) via std::push_heap/pop_heap
  uint64_t order_ = 0;
  uint64_t delivered_ = 0;
  uint64_t dropped_overflow_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace dhr::net
