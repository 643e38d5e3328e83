#include "net/udp_socket.hpp"

#include "log/log.hpp"
#include "net/clock.hpp"

// Asio's scheduler trips GCC's -Wnull-dereference after inlining (a false positive in a system
// header); silence it for Asio only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <asio/ip/udp.hpp>
#include <asio/ip/v6_only.hpp>
#include <asio/post.hpp>
#pragma GCC diagnostic pop

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace dhr::net {
namespace {

using asio::ip::udp;

PeerAddress from_endpoint(const udp::endpoint& endpoint) {
  const asio::ip::address address = endpoint.address();
  if (address.is_v4()) return PeerAddress::ipv4(address.to_v4().to_bytes(), endpoint.port());
  const asio::ip::address_v6 v6 = address.to_v6();
  // A dual-stack socket sees IPv4 peers as ::ffff:a.b.c.d; report them as the IPv4 peers they are.
  if (v6.is_v4_mapped()) {
    return PeerAddress::ipv4(asio::ip::make_address_v4(asio::ip::v4_mapped, v6).to_bytes(), endpoint.port());
  }
  return PeerAddress::ipv6(v6.to_bytes(), endpoint.port(), static_cast<uint32_t>(v6.scope_id()));
}

std::optional<udp::endpoint> to_endpoint(const PeerAddress& peer, bool v6_socket) {
  if (!peer.valid() || peer.port() == 0) return std::nullopt;
  if (peer.is_ipv4()) {
    const asio::ip::address_v4 v4(peer.ipv4_bytes());
    if (v6_socket) return udp::endpoint(asio::ip::make_address_v6(asio::ip::v4_mapped, v4), peer.port());
    return udp::endpoint(v4, peer.port());
  }
  const asio::ip::address_v6 v6(peer.bytes(), peer.scope_id());
  if (v6_socket) return udp::endpoint(v6, peer.port());
  if (v6.is_v4_mapped()) return udp::endpoint(asio::ip::make_address_v4(asio::ip::v4_mapped, v6), peer.port());
  return std::nullopt;  // an IPv4 socket cannot reach an IPv6 peer
}

asio::ip::address parse_bind_address(const std::string& text) {
  if (text.empty()) return asio::ip::address_v4::any();
  if (text == "localhost") return asio::ip::address_v4::loopback();
  asio::error_code ec;
  const asio::ip::address address = asio::ip::make_address(text, ec);
  if (ec) {
    throw std::invalid_argument("UDP bind address '" + text +
                                "' is not a numeric IPv4/IPv6 address (nor \"localhost\")");
  }
  return address;
}

void add(std::atomic<uint64_t>& counter, uint64_t value = 1) { counter.fetch_add(value, std::memory_order_relaxed); }

}  // namespace

struct UdpSocket::Impl {
  struct AtomicCounters {
    std::atomic<uint64_t> datagrams_received{0}, bytes_received{0}, datagrams_sent{0}, bytes_sent{0},
        dropped_oversize{0}, dropped_empty{0}, dropped_foreign{0}, receive_errors{0}, handler_errors{0},
        send_rejected{0}, send_queue_full{0}, send_errors{0};
  };

  // Guards the lifecycle (io, socket, thread, running, config) against concurrent send_to/stop.
  mutable std::mutex mutex;
  std::unique_ptr<asio::io_context> io;
  std::unique_ptr<udp::socket> socket;
  std::thread thread;
  bool running = false;
  bool v6_socket = false;
  PeerAddress local;
  UdpSocketConfig config;
  DatagramHandler handler;

  // Touched only by the I/O thread while running.
  std::vector<uint8_t> receive_buffer;
  udp::endpoint receive_sender;

  std::atomic<size_t> pending_sends{0};
  AtomicCounters counters;

  void start_receive() {
    socket->async_receive_from(asio::buffer(receive_buffer), receive_sender,
                               [this](const asio::error_code& ec, size_t size) { on_receive(ec, size); });
  }

  void on_receive(const asio::error_code& ec, size_t size) {
    if (ec == asio::error::operation_aborted) return;
    if (ec) {
      // E.g. ECONNREFUSED from an ICMP port-unreachable: the socket stays usable.
      add(counters.receive_errors);
      log::debug("udp: receive error on port %u: %s", local.port(), ec.message().c_str());
    } else {
      deliver(size);
    }
    start_receive();
  }

  void deliver(size_t size) {
    const int64_t now = steady_now_ns();
    const PeerAddress from = from_endpoint(receive_sender);
    if (config.accept_only_from && from != *config.accept_only_from) {
      add(counters.dropped_foreign);
      return;
    }
    if (size == 0) {
      add(counters.dropped_empty);
      return;
    }
    if (size > config.max_datagram_size) {
      add(counters.dropped_oversize);
      return;
    }
    add(counters.datagrams_received);
    add(counters.bytes_received, size);
    try {
      handler(ReceivedDatagram{std::span<const uint8_t>(receive_buffer.data(), size), from, now});
    } catch (const std::exception& e) {
      add(counters.handler_errors);
      log::error("udp: datagram handler threw: %s", e.what());
    } catch (...) {
      add(counters.handler_errors);
      log::error("udp: datagram handler threw a non-std exception");
    }
  }

  void run_io() {
    for (;;) {
      try {
        io->run();
        return;
      } catch (const std::exception& e) {
        log::error("udp: I/O thread caught: %s", e.what());
      }
    }
  }
};

UdpSocket::UdpSocket() : impl_(std::make_unique<Impl>()) {}

UdpSocket::~UdpSocket() { stop(); }

void UdpSocket::open(const UdpSocketConfig& config, DatagramHandler handler) {
  if (config.max_datagram_size == 0 || config.max_datagram_size > kMaxUdpPayload) {
    throw std::logic_error("UdpSocketConfig::max_datagram_size must be in 1.." + std::to_string(kMaxUdpPayload));
  }
  if (config.max_pending_sends == 0) throw std::logic_error("UdpSocketConfig::max_pending_sends must be > 0");
  if (!handler) throw std::logic_error("UdpSocket::open needs a datagram handler");
  {
    const std::lock_guard lock(impl_->mutex);
    if (impl_->running) throw std::logic_error("UdpSocket::open: already open");
  }
  stop();  // joins a thread left behind by a stop() requested from inside the handler

  Impl& s = *impl_;
  const std::lock_guard lock(s.mutex);
  const asio::ip::address bind_address = parse_bind_address(config.bind_address);
  auto io = std::make_unique<asio::io_context>(1);
  auto socket = std::make_unique<udp::socket>(*io);
  const udp::endpoint bind_endpoint(bind_address, config.port);
  asio::error_code ec;
  socket->open(bind_endpoint.protocol(), ec);
  if (!ec && bind_address.is_v6() && bind_address.is_unspecified()) {
    socket->set_option(asio::ip::v6_only(false), ec);  // "::" also serves IPv4 peers
    ec.clear();  // a v6-only host still works for IPv6 peers
  }
  if (!ec) socket->bind(bind_endpoint, ec);
  if (ec) {
    throw std::runtime_error("cannot bind UDP socket to " + bind_address.to_string() + ":" +
                             std::to_string(config.port) + ": " + ec.message());
  }
  asio::error_code ignored;
  if (config.receive_buffer_bytes > 0) {
    socket->set_option(asio::socket_base::receive_buffer_size(config.receive_buffer_bytes), ignored);
  }
  if (config.send_buffer_bytes > 0) {
    socket->set_option(asio::socket_base::send_buffer_size(config.send_buffer_bytes), ignored);
  }
  const udp::endpoint local = socket->local_endpoint(ec);
  if (ec) throw std::runtime_error("cannot read the bound UDP address: " + ec.message());

  s.config = config;
  s.handler = std::move(handler);
  s.v6_socket = bind_address.is_v6();
  s.local = from_endpoint(local);
  s.receive_buffer.assign(kMaxUdpPayload + 1, 0);  // any datagram fits: oversize is detected, not truncated
  s.pending_sends.store(0);
  for (std::atomic<uint64_t>* counter :
       {&s.counters.datagrams_received, &s.counters.bytes_received, &s.counters.datagrams_sent,
        &s.counters.bytes_sent, &s.counters.dropped_oversize, &s.counters.dropped_empty,
        &s.counters.dropped_foreign, &s.counters.receive_errors, &s.counters.handler_errors,
        &s.counters.send_rejected, &s.counters.send_queue_full, &s.counters.send_errors}) {
    counter->store(0);
  }
  s.io = std::move(io);
  s.socket = std::move(socket);
  s.start_receive();
  s.running = true;
  s.thread = std::thread([&s] {
    auto guard = asio::make_work_guard(*s.io);
    s.run_io();
  });
  log::debug("udp: bound %s", s.local.to_string().c_str());
}

void UdpSocket::stop() {
  Impl& s = *impl_;
  std::thread thread;
  {
    const std::lock_guard lock(s.mutex);
    if (!s.io) return;
    s.running = false;
    s.io->stop();
    if (std::this_thread::get_id() == s.thread.get_id()) return;  // the thread cannot join itself
    thread = std::move(s.thread);
  }
  if (thread.joinable()) thread.join();
  const std::lock_guard lock(s.mutex);
  if (s.socket) {
    asio::error_code ignored;
    s.socket->close(ignored);
  }
  s.socket.reset();  // before the io_context it belongs to
  s.io.reset();      // destroys queued sends and their buffers
}

bool UdpSocket::running() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->running;
}

uint16_t UdpSocket::local_port() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->running ? impl_->local.port() : 0;
}

PeerAddress UdpSocket::local_address() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->running ? impl_->local : PeerAddress();
}

bool UdpSocket::send_to(std::span<const uint8_t> datagram, const PeerAddress& to) {
  Impl& s = *impl_;
  // Copy before taking the lock, so the lock is held only for the bookkeeping and the post.
  auto data = std::make_shared<std::vector<uint8_t>>(datagram.begin(), datagram.end());
  const std::lock_guard lock(s.mutex);
  if (!s.running || datagram.empty() || datagram.size() > s.config.max_datagram_size) {
    add(s.counters.send_rejected);
    return false;
  }
  const std::optional<udp::endpoint> endpoint = to_endpoint(to, s.v6_socket);
  if (!endpoint) {
    add(s.counters.send_rejected);
    return false;
  }
  if (s.pending_sends.load(std::memory_order_relaxed) >= s.config.max_pending_sends) {
    add(s.counters.send_queue_full);
    return false;
  }
  s.pending_sends.fetch_add(1, std::memory_order_relaxed);
  asio::post(*s.io, [&s, data = std::move(data), endpoint = *endpoint]() mutable {
    const asio::const_buffer buffer = asio::buffer(*data);
    // async_send_to sends at once when it can and waits for the socket when its buffer is full, so a
    // burst is delayed rather than dropped; order is kept (the socket queues operations FIFO).
    s.socket->async_send_to(buffer, endpoint, [&s, data = std::move(data)](const asio::error_code& ec, size_t size) {
      s.pending_sends.fetch_sub(1, std::memory_order_relaxed);
      if (ec == asio::error::operation_aborted) return;
      if (ec) {
        add(s.counters.send_errors);
        log::debug("udp: send error: %s", ec.message().c_str());
        return;
      }
      add(s.counters.datagrams_sent);
      add(s.counters.bytes_sent, size);
    });
  });
  return true;
}

UdpCounters UdpSocket::counters() const {
  const Impl::AtomicCounters& c = impl_->counters;
  auto get = [](const std::atomic<uint64_t>& counter) { return counter.load(std::memory_order_relaxed); };
  UdpCounters out;
  out.datagrams_received = get(c.datagrams_received);
  out.bytes_received = get(c.bytes_received);
  out.datagrams_sent = get(c.datagrams_sent);
  out.bytes_sent = get(c.bytes_sent);
  out.dropped_oversize = get(c.dropped_oversize);
  out.dropped_empty = get(c.dropped_empty);
  out.dropped_foreign = get(c.dropped_foreign);
  out.receive_errors = get(c.receive_errors);
  out.handler_errors = get(c.handler_errors);
  out.send_rejected = get(c.send_rejected);
  out.send_queue_full = get(c.send_queue_full);
  out.send_errors = get(c.send_errors);
  return out;
}

}  // namespace dhr::net
