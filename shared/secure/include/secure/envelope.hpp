// Authenticated datagrams (docs/security.md, docs/protocol.md "Authentication"). Works on encoded datagrams
// (protocol.hpp): the 20-byte header stays in clear, so a receiver finds the session by its token before
// any cryptography, and the header's flags (bytes 6-7, zero in an unprotected datagram) say how the rest
// is protected:
//   kFlagAuthenticated  handshake datagrams (Hello, Welcome, a Bye without a session): the body in clear,
//                       then a 32-byte random and a 32-byte HMAC-SHA-512-256 tag, under a key derived from
//                       the deployment key, over everything before the tag and a `bind` the receiver knows
//                       (a Welcome's tag covers its Hello's random: an answer to this very Hello);
//   kFlagSealed         session datagrams: the body encrypted with ChaCha20-Poly1305 (IETF) under the
//                       session's key for that direction, the header as associated data, the header's
//                       sequence as the nonce, the 16-byte tag appended.
// Opening writes the plain datagram, flags cleared, into the caller's buffer (no allocation), ready for
// decode_datagram.
#pragma once
#include "protocol/protocol.hpp"
#include "secure/key.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <span>

namespace dhr::secure {

inline constexpr uint16_t kFlagSealed = 1;
inline constexpr uint16_t kFlagAuthenticated = 2;
inline constexpr size_t kRandomSize = 32;
inline constexpr size_t kHandshakeTagSize = 32;
inline constexpr size_t kHandshakeTrailerSize = kRandomSize + kHandshakeTagSize;
inline constexpr size_t kSealTagSize = 16;
static_assert(kSealTagSize == kSealOverhead, "protocol.hpp reserves the seal's tag in every datagram");

using Random = std::array<uint8_t, kRandomSize>;
Random random_bytes();  // the operating system's generator

// Header fields of an encoded datagram (0 when it is shorter than the header).
uint16_t datagram_flags(std::span<const uint8_t> bytes);
uint32_t datagram_sequence(std::span<const uint8_t> bytes);

// A session's keys, one per direction, from the deployment key, both handshake randoms and the token.
struct SessionKeys {
  Key client_to_server;
  Key server_to_client;
};
SessionKeys derive_session_keys(const Key& deployment, const Random& client, const Random& server, uint64_t token);

// The handshake tag's key (derived from the deployment key once; both sides hold one).
class HandshakeKey {
 public:
  explicit HandshakeKey(const Key& deployment);
  // out[0, plain_size) holds an encoded datagram: sets kFlagAuthenticated and appends `random` and the tag.
  // Returns the size on the wire, 0 when `out` is too small or plain_size is shorter than a header.
  size_t authenticate(std::span<uint8_t> out, size_t plain_size, const Random& random,
                      std::span<const uint8_t> bind = {}) const;
  struct Verified {
    size_t size = 0;  // of the plain datagram in `out`
    Random random{};
  };
  // Checks the flag and the tag of a handshake datagram and copies it into `out` without the trailer and
  // with the flags cleared. std::nullopt when the flag is missing, the tag does not verify or `out` is small.
  std::optional<Verified> verify(std::span<const uint8_t> wire, std::span<uint8_t> out,
                                 std::span<const uint8_t> bind = {}) const;

 private:
  Key key_;
};

// Seals the encoded datagram `plain` into `out` (kFlagSealed set; plain.size() + kSealTagSize bytes).
// Returns the size, 0 when `out` is too small or `plain` is shorter than a header. Never seal two datagrams
// with one key and one sequence number.
size_t seal(const Key& key, std::span<const uint8_t> plain, std::span<uint8_t> out);
// Opens a sealed datagram into `out` (flags cleared); std::nullopt when the flag is missing, the tag does not
// verify or `out` is too small.
std::optional<size_t> open(const Key& key, std::span<const uint8_t> wire, std::span<uint8_t> out);

}  // namespace dhr::secure
