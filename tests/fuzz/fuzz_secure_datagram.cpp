// Fuzz target: the authentication layer (secure/envelope.hpp) on arbitrary bytes, under a fixed test key:
// secure::open, HandshakeKey::verify (with and without a bind) and, fed from the same bytes, the replay
// window. Properties: no crash or sanitizer report; whatever opens is a plain datagram of the wire size
// minus the tag with its flags cleared, and sealing it again gives the same wire bytes (the seal is a
// function of key, header and body); whatever verifies re-authenticates to the same bytes; the replay
// window accepts every sequence number at most once.
#include "fuzz_support.hpp"
#include "secure/envelope.hpp"
#include "secure/replay_window.hpp"

#include <array>
#include <cstring>
#include <set>
#include <vector>

namespace {

const dhr::secure::Key& test_key() {
  static const dhr::secure::Key key = [] {
    std::array<uint8_t, dhr::secure::kKeySize> bytes{};
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i * 7 + 1);
    return dhr::secure::Key(bytes);
  }();
  return key;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace secure = dhr::secure;
  const std::span<const uint8_t> wire(data, size);
  std::array<uint8_t, dhr::kMaxDatagramSize> out{};

  if (const std::optional<size_t> n = secure::open(test_key(), wire, out)) {
    DHR_FUZZ_CHECK(*n + secure::kSealTagSize == size);
    DHR_FUZZ_CHECK(secure::datagram_flags(std::span<const uint8_t>(out.data(), *n)) == 0);
    std::vector<uint8_t> again(size);
    DHR_FUZZ_CHECK(secure::seal(test_key(), std::span<const uint8_t>(out.data(), *n), again) == size);
    DHR_FUZZ_CHECK_MSG(std::memcmp(again.data(), data, size) == 0, "re-sealed bytes differ");
  }

  static const secure::HandshakeKey handshake(test_key());
  const std::array<uint8_t, 4> bind = {1, 2, 3, 4};
  for (const bool bound : {false, true}) {
    const std::span<const uint8_t> b = bound ? std::span<const uint8_t>(bind) : std::span<const uint8_t>{};
    if (const auto v = handshake.verify(wire, out, b)) {
      DHR_FUZZ_CHECK(v->size + secure::kHandshakeTrailerSize == size);
      std::vector<uint8_t> again(size);
      std::memcpy(again.data(), out.data(), v->size);
      DHR_FUZZ_CHECK(handshake.authenticate(again, v->size, v->random, b) == size);
      DHR_FUZZ_CHECK_MSG(std::memcmp(again.data(), data, size) == 0, "re-authenticated bytes differ");
    }
  }

  // The same bytes as a stream of 16-bit sequence steps for the replay window.
  secure::ReplayWindow window;
  std::set<uint32_t> accepted;
  uint32_t sequence = 0;
  for (size_t i = 0; i + 1 < size; i += 2) {
    const int32_t step = static_cast<int16_t>(data[i] | (data[i + 1] << 8));
    sequence = static_cast<uint32_t>(static_cast<int64_t>(sequence) + step);
    if (window.accept(sequence)) DHR_FUZZ_CHECK_MSG(accepted.insert(sequence).second, "a sequence accepted twice");
  }
  return 0;
}
