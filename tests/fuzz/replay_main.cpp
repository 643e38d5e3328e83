// main() for the fuzz targets when they are built without libFuzzer (GCC, the normal build): runs the
// empty input, the target's built-in seeds, any files or directories given, then a fixed number of
// deterministic pseudo-random mutations of those inputs. Same seed -> same inputs, on every machine.
//
//   dhr_fuzz_<target> [--iterations N] [--seed S] [--max-len BYTES] [FILE|DIR]...
//
// With --iterations 0 and a file it reproduces one input (e.g. a libFuzzer crash file). When a property
// check aborts or the process crashes, the current input is written to $DHR_FUZZ_CRASH_DIR (default: the
// working directory) as replay-crash-<target>.bin first.
#include "fuzz_support.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#ifndef DHR_FUZZ_TARGET
#error "DHR_FUZZ_TARGET (the target's seed name) must be defined"
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

using dhr::fuzz::Bytes;
using dhr::fuzz::Prng;

// The input being run, for the crash handler (which may only use async-signal-safe calls).
const uint8_t* g_current = nullptr;
size_t g_current_size = 0;
char g_crash_path[4096] = {};

void on_crash(int sig) {
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    size_t done = 0;
    while (g_current && done < g_current_size) {
      const ssize_t n = ::write(fd, g_current + done, g_current_size - done);
      if (n <= 0) break;
      done += static_cast<size_t>(n);
    }
    ::close(fd);
    const char msg[] = "fuzz replay: crashing input written to ";
    [[maybe_unused]] ssize_t w = ::write(2, msg, sizeof msg - 1);
    w = ::write(2, g_crash_path, std::strlen(g_crash_path));
    w = ::write(2, "\n", 1);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void run_one(const Bytes& input) {
  g_current = input.data();
  g_current_size = input.size();
  // A null pointer for the empty input, as libFuzzer may pass.
  LLVMFuzzerTestOneInput(input.empty() ? nullptr : input.data(), input.size());
  g_current = nullptr;
}

const char* const kTokens[] = {"0",  "1",   "-1", "255", "65535", "4294967295", "1e308", "nan", "inf", "-0",
                               ",",  ", ",  "\n", "\"",  "{",     "}",          "[",     "]",   ":",   "#",
                               "0.5", "1.5707963", "\"uri\"", "\"byteLength\"", "null", "true"};

void mutate_once(Bytes& b, const std::vector<Bytes>& pool, Prng& rng, size_t max_len) {
  const size_t pos = b.empty() ? 0 : rng.below(b.size());
  switch (rng.below(10)) {
    case 0:
      if (!b.empty()) b[pos] ^= static_cast<uint8_t>(1u << rng.below(8));
      break;
    case 1:
      if (!b.empty()) b[pos] = static_cast<uint8_t>(rng.next());
      break;
    case 2: {  // an interesting little-endian value of 1, 2 or 4 bytes
      static constexpr uint32_t kValues[] = {0, 1, 0x7F, 0x80, 0xFF, 0x100, 0x7FFF, 0x8000, 0xFFFF, 0x7FFFFFFF,
                                             0x80000000u, 0xFFFFFFFFu};
      const uint32_t v = kValues[rng.below(std::size(kValues))];
      const size_t width = size_t{1} << rng.below(3);
      for (size_t k = 0; k < width && pos + k < b.size(); ++k) b[pos + k] = static_cast<uint8_t>(v >> (8 * k));
      break;
    }
    case 3: {
      const size_t n = 1 + rng.below(8);
      for (size_t k = 0; k < n; ++k) b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos), static_cast<uint8_t>(rng.next()));
      break;
    }
    case 4:
      if (!b.empty()) {
        const size_t n = std::min(b.size() - pos, 1 + rng.below(16));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(pos), b.begin() + static_cast<std::ptrdiff_t>(pos + n));
      }
      break;
    case 5:
      if (!b.empty()) {
        const size_t n = std::min(b.size() - pos, 1 + rng.below(32));
        const Bytes copy(b.begin() + static_cast<std::ptrdiff_t>(pos), b.begin() + static_cast<std::ptrdiff_t>(pos + n));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(rng.below(b.size() + 1)), copy.begin(), copy.end());
      }
      break;
    case 6: {  // splice a piece of another input in
      const Bytes& other = pool[rng.below(pool.size())];
      if (other.empty()) break;
      const size_t from = rng.below(other.size());
      const size_t n = std::min(other.size() - from, 1 + rng.below(64));
      const auto src = other.begin() + static_cast<std::ptrdiff_t>(from);
      if (rng.below(2) && pos + n <= b.size()) {
        std::copy(src, src + static_cast<std::ptrdiff_t>(n), b.begin() + static_cast<std::ptrdiff_t>(pos));
      } else {
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos), src, src + static_cast<std::ptrdiff_t>(n));
      }
      break;
    }
    case 7:
      b.resize(rng.below(b.size() + 1));
      break;
    case 8:
      if (!b.empty()) b[pos] = static_cast<uint8_t>(b[pos] + static_cast<uint8_t>(rng.below(33)) - 16);
      break;
    default: {
      const char* t = kTokens[rng.below(std::size(kTokens))];
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos), t, t + std::strlen(t));
      break;
    }
  }
  if (b.size() > max_len) b.resize(max_len);
}

bool read_input(const std::filesystem::path& path, size_t max_len, Bytes& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (out.size() > max_len) out.resize(max_len);
  return true;
}

int usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s [--iterations N] [--seed S] [--max-len BYTES] [FILE|DIR]...\n", argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string target = DHR_FUZZ_TARGET;
  uint64_t iterations = 2000, seed = 1;
  size_t max_len = 4096;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](uint64_t& out) {
      if (i + 1 >= argc) return false;
      char* end = nullptr;
      out = std::strtoull(argv[++i], &end, 10);
      return end && *end == '\0';
    };
    uint64_t v = 0;
    if (arg == "--iterations") {
      if (!value(iterations)) return usage(argv[0]);
    } else if (arg == "--seed") {
      if (!value(seed)) return usage(argv[0]);
    } else if (arg == "--max-len") {
      if (!value(v) || v == 0) return usage(argv[0]);
      max_len = static_cast<size_t>(v);
    } else if (arg.rfind("--", 0) == 0) {
      return usage(argv[0]);
    } else {
      paths.push_back(arg);
    }
  }

  const char* crash_dir = std::getenv("DHR_FUZZ_CRASH_DIR");
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s/replay-crash-%s.bin", crash_dir ? crash_dir : ".",
                target.c_str());
  for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, on_crash);

  std::vector<Bytes> pool;
  for (dhr::fuzz::Seed& s : dhr::fuzz::seeds_for(target)) {
    if (s.bytes.size() > max_len) s.bytes.resize(max_len);
    pool.push_back(std::move(s.bytes));
  }
  size_t files = 0;
  for (const std::string& p : paths) {
    std::error_code ec;
    std::vector<std::filesystem::path> found;
    if (std::filesystem::is_directory(p, ec)) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(p, ec))
        if (e.is_regular_file(ec)) found.push_back(e.path());
      std::sort(found.begin(), found.end());  // directory order is not deterministic
    } else {
      found.emplace_back(p);
    }
    for (const auto& f : found) {
      Bytes b;
      if (!read_input(f, max_len, b)) {
        std::fprintf(stderr, "fuzz replay: cannot read %s\n", f.string().c_str());
        return 2;
      }
      pool.push_back(std::move(b));
      ++files;
    }
  }

  const auto start = std::chrono::steady_clock::now();
  run_one(Bytes{});
  for (const Bytes& b : pool) run_one(b);
  Prng rng(seed);
  Bytes last;
  for (uint64_t i = 0; i < iterations && !pool.empty(); ++i) {
    // Mostly fresh mutations of a pool input; sometimes a further mutation of the previous one.
    Bytes input = (i > 0 && rng.below(4) == 0) ? last : pool[rng.below(pool.size())];
    const size_t steps = 1 + rng.below(4);
    for (size_t k = 0; k < steps; ++k) mutate_once(input, pool, rng, max_len);
    run_one(input);
    last = std::move(input);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("{\"target\": \"%s\", \"seeds\": %zu, \"files\": %zu, \"mutations\": %llu, \"seed\": %llu, "
              "\"seconds\": %.2f}\n",
              target.c_str(), pool.size() - files, files, static_cast<unsigned long long>(iterations),
              static_cast<unsigned long long>(seed), seconds);
  return 0;
}
