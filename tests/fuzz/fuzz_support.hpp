// Helpers shared by the fuzz targets, their seed generator and the replay driver: a property check that
// aborts (so libFuzzer and the replay driver both report it as a crash), a byte reader that never fails
// (missing bytes read as zero), and a small deterministic PRNG.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace dhr::fuzz {

using Bytes = std::vector<uint8_t>;

struct Seed {
  std::string name;  // file name in the corpus (no directory)
  Bytes bytes;
};

// Seeds of one target ("datagram", "shard_payload", ...); empty for an unknown name.
std::vector<Seed> seeds_for(const std::string& target);
// Every target name seeds_for knows.
std::vector<std::string> seed_targets();

[[noreturn]] inline void check_failed(const char* expression, const char* file, int line, const char* detail) {
  std::fprintf(stderr, "fuzz property violated: %s (%s:%d)%s%s\n", expression, file, line, detail[0] ? ": " : "",
               detail);
  std::fflush(stderr);
  std::abort();
}

// A property every input must satisfy; a violation is a bug in the code under test.
#define DHR_FUZZ_CHECK(cond) \
  ((cond) ? static_cast<void>(0) : ::dhr::fuzz::check_failed(#cond, __FILE__, __LINE__, ""))
#define DHR_FUZZ_CHECK_MSG(cond, msg) \
  ((cond) ? static_cast<void>(0) : ::dhr::fuzz::check_failed(#cond, __FILE__, __LINE__, (msg)))

// A known bug in the code under test, already reported (docs/fuzzing.md, "Open findings"): noted once
// on stderr and tolerated, so that the fuzzers keep looking for new problems and the replay tests stay
// green until it is fixed. With DHR_FUZZ_STRICT=1 in the environment it is fatal like any violation.
inline void known_issue(const char* id, const char* file, int line) {
  static const bool strict = [] {
    const char* v = std::getenv("DHR_FUZZ_STRICT");
    return v && v[0] == '1';
  }();
  if (strict) check_failed(id, file, line, "known issue (DHR_FUZZ_STRICT=1)");
  static std::vector<std::string> noted;
  for (const std::string& n : noted)
    if (n == id) return;
  noted.emplace_back(id);
  std::fprintf(stderr, "fuzz: known issue '%s' hit (%s:%d), tolerated; see docs/fuzzing.md\n", id, file, line);
}
#define DHR_FUZZ_KNOWN_ISSUE(id) ::dhr::fuzz::known_issue((id), __FILE__, __LINE__)

// Consumes an input from the front; past the end every read returns zero bytes, so targets never need
// to special-case short inputs.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  explicit Reader(std::span<const uint8_t> bytes) : Reader(bytes.data(), bytes.size()) {}

  uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  uint16_t u16() { return static_cast<uint16_t>(u8() | (u8() << 8)); }
  uint32_t u32() { return static_cast<uint32_t>(u16()) | (static_cast<uint32_t>(u16()) << 16); }
  uint64_t u64() { return static_cast<uint64_t>(u32()) | (static_cast<uint64_t>(u32()) << 32); }
  bool flag() { return (u8() & 1) != 0; }
  // A value in [lo, hi] (hi >= lo).
  uint32_t range(uint32_t lo, uint32_t hi) { return lo + u32() % (hi - lo + 1); }
  // Up to n bytes (fewer at the end of the input).
  std::span<const uint8_t> take(size_t n) {
    const size_t k = n < remaining() ? n : remaining();
    const std::span<const uint8_t> out(data_ + pos_, k);
    pos_ += k;
    return out;
  }
  size_t remaining() const { return size_ - pos_; }
  bool at_end() const { return pos_ >= size_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

// Little-endian appends, for seeds that must match what a target's Reader expects.
inline void put_u8(Bytes& out, uint8_t v) { out.push_back(v); }
inline void put_u16(Bytes& out, uint16_t v) {
  out.push_back(static_cast<uint8_t>(v));
  out.push_back(static_cast<uint8_t>(v >> 8));
}
inline void put_u32(Bytes& out, uint32_t v) {
  put_u16(out, static_cast<uint16_t>(v));
  put_u16(out, static_cast<uint16_t>(v >> 16));
}
inline void put_u64(Bytes& out, uint64_t v) {
  put_u32(out, static_cast<uint32_t>(v));
  put_u32(out, static_cast<uint32_t>(v >> 32));
}
inline void put_bytes(Bytes& out, std::span<const uint8_t> bytes) { out.insert(out.end(), bytes.begin(), bytes.end()); }

// splitmix64: tiny, good enough for mutations, identical everywhere.
class Prng {
 public:
  explicit Prng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform-ish in [0, n), n > 0.
  size_t below(size_t n) { return static_cast<size_t>(next() % n); }

 private:
  uint64_t state_;
};

}  // namespace dhr::fuzz
