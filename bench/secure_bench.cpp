// secure_bench: what authentication costs per datagram (docs/security.md): sealing and opening full-size
// session datagrams (ChaCha20-Poly1305), verifying a Hello's handshake tag (HMAC-SHA-512-256), deriving a
// session's keys, and the replay window; and the share of one core that sealing a visibility stream takes at
// given bit rates. Prints one JSON line; asserts nothing.
// Usage: secure_bench [--quick]
#include "json_writer.hpp"
#include "secure/envelope.hpp"
#include "secure/replay_window.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

// Median of `repeats` timings of `iterations` calls of f, in ns per call.
template <class F>
double ns_per_call(int iterations, int repeats, F&& f) {
  std::vector<double> runs;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    for (int i = 0; i < iterations; ++i) f(i);
    runs.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / iterations);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--help" || a == "-h") {
      std::printf("secure_bench [--quick]: cost of sealing, opening and handshake tags; one JSON line\n");
      return 0;
    } else {
      std::fprintf(stderr, "secure_bench: unknown argument '%s' (see --help)\n", a.c_str());
      return 2;
    }
  }
  namespace secure = dhr::secure;
  const int iterations = quick ? 2000 : 50000;
  const int repeats = quick ? 3 : 7;
  const secure::Key key = secure::Key::random();
  const secure::HandshakeKey handshake(key);

  // A full-size plain datagram (header + body) and its sealed form.
  std::vector<uint8_t> plain(dhr::kMaxPlainDatagramSize);
  for (size_t i = 0; i < plain.size(); ++i) plain[i] = static_cast<uint8_t>(i * 31 + 7);
  std::memcpy(plain.data(), "DHRX", 4);
  plain[4] = dhr::kProtocolVersion;
  plain[6] = plain[7] = 0;
  std::vector<uint8_t> sealed(plain.size() + secure::kSealTagSize);
  std::array<uint8_t, dhr::kMaxDatagramSize> out{};
  size_t sink = 0;
  const double seal_ns = ns_per_call(iterations, repeats, [&](int i) {
    plain[16] = static_cast<uint8_t>(i);  // another sequence: another nonce
    sink += secure::seal(key, plain, sealed);
  });
  plain[16] = 0;
  secure::seal(key, plain, sealed);
  const double open_ns = ns_per_call(iterations, repeats, [&](int) { sink += secure::open(key, sealed, out).value_or(0); });

  std::vector<uint8_t> hello(170 + secure::kHandshakeTrailerSize);
  std::memcpy(hello.data(), plain.data(), 170);
  handshake.authenticate(hello, 170, secure::random_bytes());
  const double verify_ns = ns_per_call(iterations / 4, repeats, [&](int) {
    sink += handshake.verify(hello, out).has_value() ? 1 : 0;
  });
  const secure::Random a = secure::random_bytes(), b = secure::random_bytes();
  const double derive_ns = ns_per_call(iterations / 4, repeats, [&](int i) {
    sink += secure::derive_session_keys(key, a, b, static_cast<uint64_t>(i)).client_to_server.data()[0];
  });
  secure::ReplayWindow window;
  const double replay_ns = ns_per_call(iterations, repeats, [&](int i) { sink += window.accept(static_cast<uint32_t>(i)); });

  const double bytes = static_cast<double>(plain.size());
  const double seal_mb_s = bytes / seal_ns * 1e3;   // MB/s (1e6 bytes)
  const double open_mb_s = bytes / open_ns * 1e3;
  // One core's share for sealing a stream of full datagrams at these rates.
  auto core_share = [&](double mbit_s) { return mbit_s * 1e6 / 8.0 / bytes * seal_ns * 1e-9; };

  dhr::bench::JsonWriter w;
  w.begin_object();
  w.value("datagram_bytes", static_cast<unsigned long long>(plain.size()));
  w.value("seal_us", seal_ns * 1e-3, 3);
  w.value("open_us", open_ns * 1e-3, 3);
  w.value("seal_mb_per_s", seal_mb_s, 1);
  w.value("open_mb_per_s", open_mb_s, 1);
  w.value("hello_verify_us", verify_ns * 1e-3, 3);
  w.value("session_keys_us", derive_ns * 1e-3, 3);
  w.value("replay_check_ns", replay_ns, 2);
  w.value("core_share_seal_4_6_mbit", core_share(4.6), 5);
  w.value("core_share_seal_104_6_mbit", core_share(104.6), 5);
  w.value("iterations", static_cast<unsigned long long>(iterations));
  w.value("checksum", static_cast<unsigned long long>(sink % 1000));
  w.end_object();
  std::string line = w.str();
  for (char& c : line)
    if (c == '\n') c = ' ';
  std::printf("%s\n", line.c_str());
  return 0;
}
