// Real UDP on loopback. Assertions are about what arrives and what is counted, never about timing:
// waits use generous timeouts and only guard against hangs.
#include "net/endpoints.hpp"
#include "net/udp_socket.hpp"
#include "wait_until.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace dhr::net {
namespace {

using test::wait_until;

std::span<const uint8_t> as_bytes(const std::string& text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

std::string as_string(std::span<const uint8_t> bytes) { return {bytes.begin(), bytes.end()}; }

// Collects datagrams from a handler thread.
struct Inbox {
  std::mutex mutex;
  std::vector<std::string> messages;
  std::vector<PeerAddress> senders;

  DatagramHandler handler() {
    return [this](const ReceivedDatagram& d) {
      const std::lock_guard lock(mutex);
      messages.push_back(as_string(d.bytes));
      senders.push_back(d.from);
    };
  }
  size_t size() {
    const std::lock_guard lock(mutex);
    return messages.size();
  }
  bool contains(const std::string& text) {
    const std::lock_guard lock(mutex);
    return std::find(messages.begin(), messages.end(), text) != messages.end();
  }
};

// An echo server on loopback; the reply is "echo:" + request.
struct EchoServer {
  ServerEndpoint endpoint;
  std::atomic<uint64_t> requests{0};

  explicit EchoServer(const std::string& bind = "127.0.0.1", size_t max_size = kDefaultMaxDatagramSize) {
    ServerEndpointConfig config;
    config.bind_address = bind;
    config.max_datagram_size = max_size;
    endpoint.start(config, [this](const ReceivedDatagram& d) {
      ++requests;
      const std::string reply = "echo:" + as_string(d.bytes);
      endpoint.send_to(as_bytes(reply), d.from);
    });
  }
};

// A raw POSIX socket, for datagrams our own sockets refuse to send (empty, oversize).
struct RawSocket {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  ~RawSocket() { close(fd); }
  bool send_to(const void* data, size_t size, uint16_t port) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return sendto(fd, data, size, 0, reinterpret_cast<const sockaddr*>(&to), sizeof(to)) == static_cast<ssize_t>(size);
  }
};

TEST(UdpEndpoint, ClientServerRoundTrip) {
  EchoServer server;
  ASSERT_NE(server.endpoint.port(), 0);
  Inbox inbox;
  ClientEndpoint client;
  ClientEndpointConfig config;
  config.server_port = server.endpoint.port();
  client.connect(config, inbox.handler());
  EXPECT_EQ(client.server_address(), PeerAddress::loopback_ipv4(server.endpoint.port()));
  EXPECT_NE(client.local_port(), 0);

  ASSERT_TRUE(client.send(as_bytes("hello")));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == 1; }));
  EXPECT_EQ(inbox.messages[0], "echo:hello");
  EXPECT_EQ(inbox.senders[0], client.server_address());

  ASSERT_TRUE(wait_until([&] { return client.counters().datagrams_sent == 1; }));
  const UdpCounters c = client.counters();
  EXPECT_EQ(c.datagrams_received, 1u);
  EXPECT_EQ(c.bytes_received, 10u);
  EXPECT_EQ(c.bytes_sent, 5u);
  EXPECT_EQ(c.received_dropped(), 0u);
  EXPECT_EQ(c.send_dropped(), 0u);
  const UdpCounters s = server.endpoint.counters();
  EXPECT_EQ(s.datagrams_received, 1u);
}

TEST(UdpEndpoint, ConnectResolvesLocalhost) {
  EchoServer server;
  Inbox inbox;
  ClientEndpoint client;
  ClientEndpointConfig config;
  config.server_host = "localhost";
  config.server_port = server.endpoint.port();
  client.connect(config, inbox.handler());
  ASSERT_TRUE(client.send(as_bytes("via-name")));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == 1; }));
  EXPECT_EQ(inbox.messages[0], "echo:via-name");
}

TEST(UdpEndpoint, Ipv6LoopbackRoundTrip) {
  std::unique_ptr<EchoServer> server;
  try {
    server = std::make_unique<EchoServer>("::1");
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no IPv6 loopback here: " << e.what();
  }
  Inbox inbox;
  ClientEndpoint client;
  ClientEndpointConfig config;
  config.server_host = "::1";
  config.server_port = server->endpoint.port();
  client.connect(config, inbox.handler());
  EXPECT_TRUE(client.server_address().is_ipv6());
  ASSERT_TRUE(client.send(as_bytes("six")));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == 1; }));
  EXPECT_EQ(inbox.messages[0], "echo:six");
}

TEST(UdpEndpoint, DualStackServerSeesIpv4ClientsAsIpv4) {
  std::unique_ptr<EchoServer> server;
  try {
    server = std::make_unique<EchoServer>("::");
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no IPv6 here: " << e.what();
  }
  std::mutex mutex;
  PeerAddress seen;
  UdpSocket probe;
  probe.open(UdpSocketConfig{}, [&](const ReceivedDatagram& d) {
    const std::lock_guard lock(mutex);
    seen = d.from;
  });
  ASSERT_TRUE(probe.send_to(as_bytes("v4"), PeerAddress::loopback_ipv4(server->endpoint.port())));
  ASSERT_TRUE(wait_until([&] {
    const std::lock_guard lock(mutex);
    return seen.valid();
  }));
  // The reply went back to the IPv4 peer the server saw (not a ::ffff: mapped address).
  EXPECT_TRUE(seen.is_ipv4());
  EXPECT_EQ(seen.port(), server->endpoint.port());
}

TEST(UdpEndpoint, ManyClientsEachGetTheirOwnReplies) {
  EchoServer server;
  constexpr int kClients = 8;
  constexpr int kMessages = 50;
  std::vector<std::thread> threads;
  std::atomic<int> failures{0};
  for (int c = 0; c < kClients; ++c) {
    threads.emplace_back([&, c] {
      Inbox inbox;
      ClientEndpoint client;
      ClientEndpointConfig config;
      config.server_port = server.endpoint.port();
      client.connect(config, inbox.handler());
      // Lock-step: one request in flight per client keeps the loopback queues short (no loss).
      for (int m = 0; m < kMessages; ++m) {
        const std::string request = "client" + std::to_string(c) + "/" + std::to_string(m);
        if (!client.send(as_bytes(request)) ||
            !wait_until([&] { return inbox.size() == static_cast<size_t>(m + 1); })) {
          ++failures;
          return;
        }
      }
      const std::lock_guard lock(inbox.mutex);
      for (int m = 0; m < kMessages; ++m) {
        if (inbox.messages[static_cast<size_t>(m)] != "echo:client" + std::to_string(c) + "/" + std::to_string(m)) {
          ++failures;
        }
      }
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(server.requests.load(), static_cast<uint64_t>(kClients * kMessages));
  EXPECT_EQ(server.endpoint.counters().datagrams_received, static_cast<uint64_t>(kClients * kMessages));
}

TEST(UdpEndpoint, OversizeAndEmptyDatagramsAreCountedAndDropped) {
  Inbox inbox;
  UdpSocket receiver;
  UdpSocketConfig config;
  config.max_datagram_size = 1200;
  receiver.open(config, inbox.handler());
  const uint16_t port = receiver.local_port();

  RawSocket raw;
  ASSERT_GE(raw.fd, 0);
  const std::vector<uint8_t> big(1201, 0x55);
  const std::vector<uint8_t> max(1200, 0x66);
  const std::vector<uint8_t> huge(60000, 0x77);
  ASSERT_TRUE(raw.send_to(big.data(), big.size(), port));
  ASSERT_TRUE(raw.send_to("", 0, port));
  ASSERT_TRUE(raw.send_to(huge.data(), huge.size(), port));
  ASSERT_TRUE(raw.send_to(max.data(), max.size(), port));
  ASSERT_TRUE(raw.send_to("marker", 6, port));
  // Loopback keeps one sender's order, so when the marker is in, everything before it was handled.
  ASSERT_TRUE(wait_until([&] { return inbox.contains("marker"); }));
  const UdpCounters c = receiver.counters();
  EXPECT_EQ(c.dropped_oversize, 2u);
  EXPECT_EQ(c.dropped_empty, 1u);
  EXPECT_EQ(c.datagrams_received, 2u);
  EXPECT_EQ(inbox.size(), 2u);
  EXPECT_EQ(inbox.messages[0].size(), 1200u);
}

TEST(UdpEndpoint, SendRefusalsAreCounted) {
  Inbox inbox;
  UdpSocket socket;
  UdpSocketConfig config;
  config.max_datagram_size = 100;
  socket.open(config, inbox.handler());
  const PeerAddress self = socket.local_address();
  EXPECT_FALSE(socket.send_to({}, self));
  EXPECT_FALSE(socket.send_to(std::vector<uint8_t>(101, 1), self));
  EXPECT_FALSE(socket.send_to(as_bytes("x"), PeerAddress()));
  EXPECT_FALSE(socket.send_to(as_bytes("x"), *PeerAddress::parse("[::1]:9")));  // IPv4 socket
  EXPECT_EQ(socket.counters().send_rejected, 4u);
  ASSERT_TRUE(socket.send_to(std::vector<uint8_t>(100, 1), self));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == 1; }));
  socket.stop();
  EXPECT_FALSE(socket.send_to(as_bytes("after stop"), self));
  EXPECT_EQ(socket.counters().send_rejected, 5u);
}

TEST(UdpEndpoint, ClientDropsDatagramsFromStrangers) {
  EchoServer server;
  Inbox inbox;
  ClientEndpoint client;
  ClientEndpointConfig config;
  config.server_port = server.endpoint.port();
  client.connect(config, inbox.handler());

  RawSocket stranger;
  ASSERT_TRUE(stranger.send_to("spoof", 5, client.local_port()));
  ASSERT_TRUE(wait_until([&] { return client.counters().dropped_foreign == 1; }));
  ASSERT_TRUE(client.send(as_bytes("real")));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == 1; }));
  EXPECT_EQ(inbox.messages[0], "echo:real");
  EXPECT_FALSE(inbox.contains("spoof"));
}

TEST(UdpEndpoint, StopIsIdempotentAndRestartWorks) {
  Inbox inbox;
  UdpSocket socket;
  EXPECT_FALSE(socket.running());
  socket.stop();  // never opened: fine
  for (int round = 0; round < 3; ++round) {
    socket.open(UdpSocketConfig{}, inbox.handler());
    EXPECT_TRUE(socket.running());
    const std::string text = "round" + std::to_string(round);
    ASSERT_TRUE(socket.send_to(as_bytes(text), socket.local_address()));
    ASSERT_TRUE(wait_until([&] { return inbox.contains(text); }));
    EXPECT_EQ(socket.counters().datagrams_received, 1u);  // counters restart with each open
    socket.stop();
    socket.stop();
    EXPECT_FALSE(socket.running());
    EXPECT_EQ(socket.local_port(), 0);
  }
  EXPECT_THROW(socket.open(UdpSocketConfig{}, nullptr), std::logic_error);
  socket.open(UdpSocketConfig{}, inbox.handler());
  EXPECT_THROW(socket.open(UdpSocketConfig{}, inbox.handler()), std::logic_error);
  // The destructor stops the running socket.
}

TEST(UdpEndpoint, RestartOnTheSamePort) {
  Inbox inbox;
  UdpSocket socket;
  socket.open(UdpSocketConfig{}, inbox.handler());
  UdpSocketConfig same_port;
  same_port.port = socket.local_port();
  socket.stop();
  socket.open(same_port, inbox.handler());
  EXPECT_EQ(socket.local_port(), same_port.port);
  ASSERT_TRUE(socket.send_to(as_bytes("again"), socket.local_address()));
  ASSERT_TRUE(wait_until([&] { return inbox.contains("again"); }));
}

TEST(UdpEndpoint, StopFromInsideTheHandlerDoesNotDeadlock) {
  UdpSocket socket;
  std::atomic<int> calls{0};
  socket.open(UdpSocketConfig{}, [&](const ReceivedDatagram&) {
    ++calls;
    socket.stop();
  });
  ASSERT_TRUE(socket.send_to(as_bytes("stop"), socket.local_address()));
  ASSERT_TRUE(wait_until([&] { return !socket.running(); }));
  EXPECT_EQ(calls.load(), 1);
  // Re-open joins the finished I/O thread first.
  socket.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  EXPECT_TRUE(socket.running());
}

TEST(UdpEndpoint, HandlerExceptionsAreCountedAndReceivingContinues) {
  Inbox inbox;
  UdpSocket socket;
  socket.open(UdpSocketConfig{}, [&](const ReceivedDatagram& d) {
    if (as_string(d.bytes) == "throw") throw std::runtime_error("handler failure");
    inbox.handler()(d);
  });
  ASSERT_TRUE(socket.send_to(as_bytes("throw"), socket.local_address()));
  ASSERT_TRUE(socket.send_to(as_bytes("fine"), socket.local_address()));
  ASSERT_TRUE(wait_until([&] { return inbox.contains("fine"); }));
  EXPECT_EQ(socket.counters().handler_errors, 1u);
}

TEST(UdpEndpoint, BindErrorsAreClear) {
  UdpSocket first;
  first.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  UdpSocket second;
  UdpSocketConfig same;
  same.port = first.local_port();
  try {
    second.open(same, [](const ReceivedDatagram&) {});
    FAIL() << "binding a port in use must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(same.port)), std::string::npos) << e.what();
  }
  EXPECT_FALSE(second.running());

  UdpSocketConfig bad_address;
  bad_address.bind_address = "not-an-address";
  EXPECT_THROW(second.open(bad_address, [](const ReceivedDatagram&) {}), std::invalid_argument);
  UdpSocketConfig bad_size;
  bad_size.max_datagram_size = 0;
  EXPECT_THROW(second.open(bad_size, [](const ReceivedDatagram&) {}), std::logic_error);

  ClientEndpoint client;
  ClientEndpointConfig no_port;
  EXPECT_THROW(client.connect(no_port, [](const ReceivedDatagram&) {}), std::runtime_error);
  ClientEndpointConfig no_host;
  no_host.server_host = "";
  no_host.server_port = 9;
  EXPECT_THROW(client.connect(no_host, [](const ReceivedDatagram&) {}), std::runtime_error);
}

TEST(UdpEndpoint, BurstOfSendsIsNotDroppedByTheSender) {
  // A frame's worth of shards leaves in one burst; the fire-and-forget path must not drop any of it.
  Inbox inbox;
  UdpSocket receiver;
  receiver.open(UdpSocketConfig{}, inbox.handler());
  UdpSocket sender;
  sender.open(UdpSocketConfig{}, [](const ReceivedDatagram&) {});
  constexpr int kBurst = 100;
  for (int i = 0; i < kBurst; ++i) {
    ASSERT_TRUE(sender.send_to(std::vector<uint8_t>(1200, static_cast<uint8_t>(i)), receiver.local_address()));
  }
  ASSERT_TRUE(wait_until([&] { return sender.counters().datagrams_sent + sender.counters().send_errors == kBurst; }));
  EXPECT_EQ(sender.counters().datagrams_sent, static_cast<uint64_t>(kBurst));
  ASSERT_TRUE(wait_until([&] { return inbox.size() == kBurst; }));
}

}  // namespace
}  // namespace dhr::net
