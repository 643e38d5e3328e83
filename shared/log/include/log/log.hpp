// Minimal leveled logging to stderr, printf-style (GCC 12 has no <format>).
// Level from the environment variable DHR_LOG (error|warn|info|debug), default info.
#pragma once

namespace dhr::log {

enum class Level { kError = 0, kWarn = 1, kInfo = 2, kDebug = 3 };

Level level();
void set_level(Level level);

void error(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void warn(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void info(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void debug(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace dhr::log
