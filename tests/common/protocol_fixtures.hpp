// Sample protocol messages with every field set, shared by the protocol unit tests
// (tests/unit/protocol_robustness_test.cpp) and the fuzz seeds (tests/fuzz/fuzz_seeds.cpp).
#pragma once
#include "protocol/protocol.hpp"

#include <cstdint>
#include <vector>

namespace dhr::test {

inline constexpr uint64_t kSampleToken = 0x0123456789ABCDEFull;

// An eye view with a non-trivial pose and an asymmetric FOV, `x` metres along X.
View sample_view(double x);

// One datagram of each message type, in this order: [0] Hello (token 0, as a client sends it), [1] Welcome,
// [2] PoseUpdate, [3] the first shard of a real encoded visibility buffer, [4] Heartbeat, [5] Bye; the others
// carry kSampleToken, sequence numbers 1..6.
std::vector<Datagram> sample_datagrams();

}  // namespace dhr::test
