#include "log/log.hpp"

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace dhr::log {
namespace {

Level level_from_env() {
  const char* env = std::getenv("DHR_LOG");
  if (env == nullptr) return Level::kInfo;
  if (std::strcmp(env, "error") == 0) return Level::kError;
  if (std::strcmp(env, "warn") == 0) return Level::kWarn;
  if (std::strcmp(env, "debug") == 0) return Level::kDebug;
  return Level::kInfo;
}

std::atomic<int>& level_storage() {
  static std::atomic<int> value{static_cast<int>(level_from_env())};
  return value;
}

// The format attribute lets the compiler check that callers pass their own (checked) format through.
__attribute__((format(printf, 2, 0))) void vwrite(Level lvl, const char* fmt, va_list args) {
  static std::mutex mutex;
  static const char* const kNames[] = {"error", "warn", "info", "debug"};
  char buffer[2048];
  std::vsnprintf(buffer, sizeof(buffer), fmt, args);
  std::lock_guard lock(mutex);
  std::fprintf(stderr, "[dhr %s] %s\n", kNames[static_cast<int>(lvl)], buffer);
}

}  // namespace

Level level() { return static_cast<Level>(level_storage().load(std::memory_order_relaxed)); }
void set_level(Level lvl) { level_storage().store(static_cast<int>(lvl), std::memory_order_relaxed); }

#define DHR_LOG_DEFINE(fn, lvl)            \
  void fn(const char* fmt, ...) {          \
    if (level() < (lvl)) return;           \
    va_list args;                          \
    va_start(args, fmt);                   \
    vwrite((lvl), fmt, args);              \
    va_end(args);                          \
  }
DHR_LOG_DEFINE(error, Level::kError)
DHR_LOG_DEFINE(warn, Level::kWarn)
DHR_LOG_DEFINE(info, Level::kInfo)
DHR_LOG_DEFINE(debug, Level::kDebug)
#undef DHR_LOG_DEFINE

}  // namespace dhr::log
