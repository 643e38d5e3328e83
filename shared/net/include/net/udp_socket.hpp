// UdpSocket: one bound UDP socket with its own I/O thread (an asio::io_context). Received datagrams go
// to a handler on that thread; sends are fire and forget (copied, queued to the I/O thread, never
// blocking the caller on the network). Oversize and empty datagrams are counted and dropped before the
// handler sees them. Asio stays in udp_socket.cpp (pimpl): this header is cheap to include.
#pragma once
#include "net/peer_address.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace dhr::net {

// Default size limit for datagrams either way: below a 1500-byte Ethernet MTU minus IP/UDP headers, so
// nothing is fragmented. The protocol's own limit (protocol/wire_layout.hpp kMaxDatagramSize) is smaller; its
// users pass it in the configs below.
inline constexpr size_t kDefaultMaxDatagramSize = 1400;
inline constexpr size_t kMaxUdpPayload = 65507;  // IPv4 limit; receive buffers are this large

struct ReceivedDatagram {
  std::span<const uint8_t> bytes;  // valid only during the handler call
  PeerAddress from;                // IPv4-mapped IPv6 senders are reported as plain IPv4
  int64_t receive_time_ns = 0;     // steady_now_ns() right after the socket returned it
};

// Runs on the socket's I/O thread, one call at a time. Exceptions are caught and counted.
using DatagramHandler = std::function<void(const ReceivedDatagram& datagram)>;

// Anything that can send a datagram to a peer: a socket, an endpoint, an impairment wrapper.
class DatagramSender {
 public:
  virtual ~DatagramSender() = default;
  // Fire and forget. False when refused (not running, empty, oversize, invalid address, queue full);
  // refusals and later OS errors are counted by the implementation. Never blocks on the network.
  virtual bool send_to(std::span<const uint8_t> datagram, const PeerAddress& to) = 0;
};

struct UdpSocketConfig {
  // Numeric IPv4/IPv6 literal, "localhost" (127.0.0.1), or "" (0.0.0.0). "::" binds dual-stack.
  std::string bind_address = "127.0.0.1";
  uint16_t port = 0;  // 0: the OS picks a free port (see local_port())
  size_t max_datagram_size = kDefaultMaxDatagramSize;  // 1..kMaxUdpPayload
  size_t max_pending_sends = 4096;       // sends queued for the I/O thread beyond this are dropped
  int receive_buffer_bytes = 1 << 20;    // SO_RCVBUF request (the kernel may cap it); 0: OS default
  int send_buffer_bytes = 1 << 20;       // SO_SNDBUF request; 0: OS default
  std::optional<PeerAddress> accept_only_from;  // when set, datagrams from anyone else are dropped
};

struct UdpCounters {
  uint64_t datagrams_received = 0;  // handed to the handler
  uint64_t bytes_received = 0;
  uint64_t datagrams_sent = 0;      // accepted by the OS
  uint64_t bytes_sent = 0;
  uint64_t dropped_oversize = 0;    // received, larger than max_datagram_size
  uint64_t dropped_empty = 0;       // received, zero bytes
  uint64_t dropped_foreign = 0;     // received from an address other than accept_only_from
  uint64_t receive_errors = 0;      // the OS reported a receive error
  uint64_t handler_errors = 0;      // the handler threw
  uint64_t send_rejected = 0;       // send_to refused: not running, empty, oversize, bad address
  uint64_t send_queue_full = 0;     // send_to refused: max_pending_sends reached
  uint64_t send_errors = 0;         // the OS reported a send error

  uint64_t received_dropped() const { return dropped_oversize + dropped_empty + dropped_foreign; }
  uint64_t send_dropped() const { return send_rejected + send_queue_full + send_errors; }
};

class UdpSocket final : public DatagramSender {
 public:
  UdpSocket();
  ~UdpSocket() override;  // stop()
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Binds and starts the I/O thread. Throws std::invalid_argument when the bind address is not one,
  // std::runtime_error with the address and the OS reason (port in use, address not on this host), and
  // std::logic_error when already open or the config is otherwise invalid.
  // Counters restart from zero.
  void open(const UdpSocketConfig& config, DatagramHandler handler);

  // Stops the I/O thread and closes the socket; queued sends are discarded. Idempotent; open() may be
  // called again afterwards. Called from inside the handler it only requests the stop (the thread
  // cannot join itself); the next stop() or the destructor joins.
  void stop();

  bool running() const;
  uint16_t local_port() const;        // 0 when not open
  PeerAddress local_address() const;  // invalid when not open

  bool send_to(std::span<const uint8_t> datagram, const PeerAddress& to) override;

  UdpCounters counters() const;  // snapshot, any thread; kept after stop() until the next open()

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dhr::net
