#include "net/endpoints.hpp"
#include "net/peer_address.hpp"

#include <gtest/gtest.h>

#include <unordered_set>

namespace dhr::net {
namespace {

TEST(PeerAddress, ParsesAndPrintsIpv4AndIpv6) {
  const auto v4 = PeerAddress::parse("127.0.0.1:4000");
  ASSERT_TRUE(v4.has_value());
  EXPECT_TRUE(v4->is_ipv4());
  EXPECT_EQ(v4->port(), 4000);
  EXPECT_TRUE(v4->is_loopback());
  EXPECT_EQ(v4->to_string(), "127.0.0.1:4000");
  EXPECT_EQ(*v4, PeerAddress::loopback_ipv4(4000));

  const auto v6 = PeerAddress::parse("[::1]:65535");
  ASSERT_TRUE(v6.has_value());
  EXPECT_TRUE(v6->is_ipv6());
  EXPECT_TRUE(v6->is_loopback());
  EXPECT_EQ(v6->to_string(), "[::1]:65535");

  const auto scoped = PeerAddress::parse("[fe80::1%3]:9");
  ASSERT_TRUE(scoped.has_value());
  EXPECT_EQ(scoped->scope_id(), 3u);
  EXPECT_EQ(scoped->to_string(), "[fe80::1%3]:9");
  EXPECT_FALSE(scoped->is_loopback());
}

TEST(PeerAddress, RejectsMalformedText) {
  for (const char* text : {"", "127.0.0.1", "127.0.0.1:", "127.0.0.1:0", "127.0.0.1:65536", "127.0.0.1:-1",
                           "127.0.0.1:80x", "1.2.3:80", "256.0.0.1:80", "localhost:80", "[::1]", "[::1:80",
                           "::1:80", "[::1]x80", "[fe80::1%]:80", "[fe80::1%eth0]:80", "[]:80", "a b:80"}) {
    EXPECT_FALSE(PeerAddress::parse(text).has_value()) << text;
  }
  EXPECT_FALSE(PeerAddress().valid());
  EXPECT_EQ(PeerAddress().to_string(), "<none>");
}

TEST(PeerAddress, EqualityAndHashDistinguishPortAndFamily) {
  std::unordered_set<PeerAddress, PeerAddressHash> set;
  set.insert(*PeerAddress::parse("127.0.0.1:1000"));
  set.insert(*PeerAddress::parse("127.0.0.1:1001"));
  set.insert(*PeerAddress::parse("[::1]:1000"));
  set.insert(*PeerAddress::parse("127.0.0.1:1000"));
  EXPECT_EQ(set.size(), 3u);
  EXPECT_NE(*PeerAddress::parse("127.0.0.1:1000"), *PeerAddress::parse("127.0.0.2:1000"));
}

TEST(SplitHostPort, HandlesNamesLiteralsAndDefaults) {
  std::string host;
  uint16_t port = 0;
  ASSERT_TRUE(split_host_port("localhost:7000", host, port));
  EXPECT_EQ(host, "localhost");
  EXPECT_EQ(port, 7000);
  ASSERT_TRUE(split_host_port("[::1]:7001", host, port));
  EXPECT_EQ(host, "::1");
  EXPECT_EQ(port, 7001);
  ASSERT_TRUE(split_host_port("::1", host, port, 7002));
  EXPECT_EQ(host, "::1");
  EXPECT_EQ(port, 7002);
  ASSERT_TRUE(split_host_port("example.org", host, port, 7003));
  EXPECT_EQ(port, 7003);
  EXPECT_FALSE(split_host_port("example.org", host, port));  // no port, no default
  EXPECT_FALSE(split_host_port(":7000", host, port));
  EXPECT_FALSE(split_host_port("host:", host, port));
  EXPECT_FALSE(split_host_port("host:99999", host, port));
  EXPECT_FALSE(split_host_port("", host, port, 1));
}

TEST(ResolveHost, LocalhostAndLiteralsResolveWithIpv4First) {
  std::string error;
  const auto localhost = resolve_host("localhost", 1234, &error);
  ASSERT_FALSE(localhost.empty()) << error;
  EXPECT_TRUE(localhost.front().is_ipv4());
  EXPECT_EQ(localhost.front().to_string(), "127.0.0.1:1234");

  const auto v6 = resolve_host("::1", 99, &error);
  ASSERT_EQ(v6.size(), 1u) << error;
  EXPECT_EQ(v6.front().to_string(), "[::1]:99");
}

TEST(ResolveHost, FailureReportsTheReason) {
  std::string error;
  EXPECT_TRUE(resolve_host("", 80, &error).empty());
  EXPECT_NE(error.find("cannot resolve"), std::string::npos) << error;
}

}  // namespace
}  // namespace dhr::net
