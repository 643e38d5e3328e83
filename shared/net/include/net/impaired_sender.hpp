// ImpairedSender: puts the impairment model in front of a real sender (a UdpSocket or endpoint), on the
// real monotonic clock. Each datagram is copied and held on a timer thread until the model's delivery
// time, then handed to the inner sender (twice when duplicated, never when lost). This is how
// --net-* options impair a real run without root or netem: each side impairs what it sends.
// With an inactive model (all zero) datagrams go straight through on the caller's thread.
#pragma once
#include "net/impairment.hpp"
#include "net/udp_socket.hpp"

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace dhr::net {

struct ImpairedSenderStats {
  ImpairmentStats model;          // what the impairment model decided
  uint64_t forwarded = 0;         // copies the inner sender accepted
  uint64_t forward_refused = 0;   // copies the inner sender refused (see its counters)
  uint64_t dropped_overflow = 0;  // refused because max_in_flight copies were held
  uint64_t rejected = 0;          // empty datagrams refused
  uint64_t in_flight = 0;         // copies held now
};

class ImpairedSender final : public DatagramSender {
 public:
  // `inner` must outlive this object. Throws std::invalid_argument when the params are invalid.
  ImpairedSender(DatagramSender& inner, const ImpairmentParams& params, size_t max_in_flight = 65536);
  ~ImpairedSender() override;  // stops the timer thread; datagrams still held are discarded
  ImpairedSender(const ImpairedSender&) = delete;
  ImpairedSender& operator=(const ImpairedSender&) = delete;

  // Never blocks on the network or the delay: the copy is queued and this returns.
  bool send_to(std::span<const uint8_t> datagram, const PeerAddress& to) override;

  // Waits until nothing is held (everything forwarded or discarded as lost) or the timeout passes.
  // For orderly shutdown (let a final Bye out) and tests. True when idle.
  bool wait_idle(int64_t timeout_ns);

  ImpairedSenderStats stats() const;
  const ImpairmentParams& params() const { return params_; }

 private:
  struct Held {
    int64_t delivery_ns = 0;
    uint64_t order = 0;
    PeerAddress to;
    std::vector<uint8_t> bytes;
  };
  void run();

  DatagramSender& inner_;
  const ImpairmentParams params_;
  const size_t max_in_flight_;
  const bool passthrough_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;  // the timer thread: new earliest datagram, or stop
  std::condition_variable idle_;  // wait_idle()
  ImpairmentModel model_;
  std::vector<Held> heap_;  // min-heap on (delivery_ns, order)
  uint64_t order_ = 0;
  size_t forwarding_ = 0;   // copies taken off the heap and not yet forwarded
  bool stopping_ = false;
  uint64_t forwarded_ = 0;
  uint64_t forward_refused_ = 0;
  uint64_t dropped_overflow_ = 0;
  uint64_t rejected_ = 0;
  std::thread thread_;  // last member: started after everything else is constructed
};

}  // namespace dhr::net
