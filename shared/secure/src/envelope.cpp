#include "secure/envelope.hpp"

#include "sodium_init.hpp"

#include <sodium.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace dhr::secure {

void ensure_sodium() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] { ok = sodium_init() >= 0; });
  if (!ok) throw std::runtime_error("libsodium failed to initialise");
}

namespace {

static_assert(crypto_kdf_KEYBYTES == kKeySize);
static_assert(crypto_auth_hmacsha512256_KEYBYTES == kKeySize);
static_assert(crypto_auth_hmacsha512256_BYTES == kHandshakeTagSize);
static_assert(crypto_aead_chacha20poly1305_ietf_KEYBYTES == kKeySize);
static_assert(crypto_aead_chacha20poly1305_ietf_ABYTES == kSealTagSize);
static_assert(crypto_aead_chacha20poly1305_ietf_NPUBBYTES == 12);

constexpr size_t kFlagsOffset = 6;
constexpr size_t kSequenceOffset = 16;
constexpr char kHandshakeContext[crypto_kdf_CONTEXTBYTES + 1] = "DHRXR-hs";
constexpr char kSessionContext[crypto_kdf_CONTEXTBYTES + 1] = "DHRXRses";
constexpr char kSessionLabel[] = "DHR-XR session 1";

void set_flags(uint8_t* header, uint16_t flags) {
  header[kFlagsOffset] = static_cast<uint8_t>(flags & 0xFF);
  header[kFlagsOffset + 1] = static_cast<uint8_t>(flags >> 8);
}

std::array<uint8_t, 12> nonce_of(const uint8_t* header) {
  std::array<uint8_t, 12> nonce{};
  std::memcpy(nonce.data(), header + kSequenceOffset, 4);  // the sequence, little-endian; the rest zero
  return nonce;
}

void handshake_tag(const Key& key, std::span<const uint8_t> covered, std::span<const uint8_t> bind,
                   uint8_t* tag) {
  crypto_auth_hmacsha512256_state state;
  crypto_auth_hmacsha512256_init(&state, key.data(), key.size());
  crypto_auth_hmacsha512256_update(&state, covered.data(), covered.size());
  if (!bind.empty()) crypto_auth_hmacsha512256_update(&state, bind.data(), bind.size());
  crypto_auth_hmacsha512256_final(&state, tag);
  sodium_memzero(&state, sizeof state);
}

}  // namespace

Random random_bytes() {
  ensure_sodium();
  Random r;
  randombytes_buf(r.data(), r.size());
  return r;
}

uint16_t datagram_flags(std::span<const uint8_t> bytes) {
  if (bytes.size() < kHeaderSize) return 0;
  return static_cast<uint16_t>(bytes[kFlagsOffset] | (bytes[kFlagsOffset + 1] << 8));
}

uint32_t datagram_sequence(std::span<const uint8_t> bytes) {
  if (bytes.size() < kHeaderSize) return 0;
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | bytes[kSequenceOffset + static_cast<size_t>(i)];
  return v;
}

SessionKeys derive_session_keys(const Key& deployment, const Random& client, const Random& server, uint64_t token) {
  ensure_sodium();
  std::array<uint8_t, sizeof(kSessionLabel) - 1 + 2 * kRandomSize + 8> input{};
  size_t at = 0;
  std::memcpy(input.data(), kSessionLabel, sizeof(kSessionLabel) - 1);
  at += sizeof(kSessionLabel) - 1;
  std::memcpy(input.data() + at, client.data(), kRandomSize);
  at += kRandomSize;
  std::memcpy(input.data() + at, server.data(), kRandomSize);
  at += kRandomSize;
  for (int i = 0; i < 8; ++i) input[at + static_cast<size_t>(i)] = static_cast<uint8_t>(token >> (8 * i));
  Key master;
  crypto_generichash(master.data(), master.size(), input.data(), input.size(), deployment.data(), deployment.size());
  SessionKeys keys;
  crypto_kdf_derive_from_key(keys.client_to_server.data(), kKeySize, 1, kSessionContext, master.data());
  crypto_kdf_derive_from_key(keys.server_to_client.data(), kKeySize, 2, kSessionContext, master.data());
  return keys;
}

HandshakeKey::HandshakeKey(const Key& deployment) {
  ensure_sodium();
  crypto_kdf_derive_from_key(key_.data(), kKeySize, 1, kHandshakeContext, deployment.data());
}

size_t HandshakeKey::authenticate(std::span<uint8_t> out, size_t plain_size, const Random& random,
                                  std::span<const uint8_t> bind) const {
  if (plain_size < kHeaderSize || plain_size + kHandshakeTrailerSize > out.size()) return 0;
  set_flags(out.data(), kFlagAuthenticated);
  std::memcpy(out.data() + plain_size, random.data(), kRandomSize);
  handshake_tag(key_, out.first(plain_size + kRandomSize), bind, out.data() + plain_size + kRandomSize);
  return plain_size + kHandshakeTrailerSize;
}

std::optional<HandshakeKey::Verified> HandshakeKey::verify(std::span<const uint8_t> wire, std::span<uint8_t> out,
                                                           std::span<const uint8_t> bind) const {
  if (wire.size() < kHeaderSize + kHandshakeTrailerSize || datagram_flags(wire) != kFlagAuthenticated) {
    return std::nullopt;
  }
  const size_t plain = wire.size() - kHandshakeTrailerSize;
  if (plain > out.size()) return std::nullopt;
  std::array<uint8_t, kHandshakeTagSize> tag;
  handshake_tag(key_, wire.first(plain + kRandomSize), bind, tag.data());
  if (crypto_verify_32(tag.data(), wire.data() + plain + kRandomSize) != 0) return std::nullopt;
  Verified v;
  v.size = plain;
  std::memcpy(v.random.data(), wire.data() + plain, kRandomSize);
  std::memcpy(out.data(), wire.data(), plain);
  set_flags(out.data(), 0);
  return v;
}

size_t seal(const Key& key, std::span<const uint8_t> plain, std::span<uint8_t> out) {
  if (plain.size() < kHeaderSize || plain.size() + kSealTagSize > out.size()) return 0;
  std::memcpy(out.data(), plain.data(), kHeaderSize);
  set_flags(out.data(), kFlagSealed);
  const std::array<uint8_t, 12> nonce = nonce_of(out.data());
  unsigned long long tag_size = 0;
  crypto_aead_chacha20poly1305_ietf_encrypt_detached(
      out.data() + kHeaderSize, out.data() + plain.size(), &tag_size, plain.data() + kHeaderSize,
      plain.size() - kHeaderSize, out.data(), kHeaderSize, nullptr, nonce.data(), key.data());
  return plain.size() + kSealTagSize;
}

std::optional<size_t> open(const Key& key, std::span<const uint8_t> wire, std::span<uint8_t> out) {
  if (wire.size() < kHeaderSize + kSealTagSize || datagram_flags(wire) != kFlagSealed) return std::nullopt;
  const size_t plain = wire.size() - kSealTagSize;
  if (plain > out.size()) return std::nullopt;
  const std::array<uint8_t, 12> nonce = nonce_of(wire.data());
  if (crypto_aead_chacha20poly1305_ietf_decrypt_detached(out.data() + kHeaderSize, nullptr, wire.data() + kHeaderSize,
                                                         plain - kHeaderSize, wire.data() + plain, wire.data(),
                                                         kHeaderSize, nonce.data(), key.data()) != 0) {
    return std::nullopt;
  }
  std::memcpy(out.data(), wire.data(), kHeaderSize);
  set_flags(out.data(), 0);
  return plain;
}

}  // namespace dhr::secure
