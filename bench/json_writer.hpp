// A minimal streaming JSON writer for the benchmarks (pretty-printed, no dependencies).
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace dhr::bench {

class JsonWriter {
 public:
  JsonWriter& begin_object(const char* key = nullptr) { return open(key, '{'); }
  JsonWriter& end_object() { return close('}'); }
  JsonWriter& begin_array(const char* key = nullptr) { return open(key, '['); }
  JsonWriter& end_array() { return close(']'); }

  JsonWriter& value(const char* key, const std::string& v) {
    prefix(key);
    out_ += quote(v);
    return *this;
  }
  JsonWriter& value(const char* key, const char* v) { return value(key, std::string(v)); }
  JsonWriter& value(const char* key, bool v) {
    prefix(key);
    out_ += v ? "true" : "false";
    return *this;
  }
  JsonWriter& value(const char* key, double v, int decimals = 3) {
    prefix(key);
    if (!std::isfinite(v)) {
      out_ += "null";
    } else {
      char b[64];
      std::snprintf(b, sizeof b, "%.*f", decimals, v);
      out_ += b;
    }
    return *this;
  }
  JsonWriter& value(const char* key, unsigned long long v) {
    prefix(key);
    out_ += std::to_string(v);
    return *this;
  }
  JsonWriter& value(const char* key, unsigned long v) { return value(key, static_cast<unsigned long long>(v)); }
  JsonWriter& value(const char* key, unsigned v) { return value(key, static_cast<unsigned long long>(v)); }
  JsonWriter& value(const char* key, int v) {
    prefix(key);
    out_ += std::to_string(v);
    return *this;
  }
  // Array elements: key nullptr.
  const std::string& str() const { return out_; }

  static std::string quote(const std::string& s) {
    std::string q = "\"";
    for (const char c : s) {
      if (c == '"' || c == '\\') {
        q += '\\';
        q += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char b[8];
        std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
        q += b;
      } else {
        q += c;
      }
    }
    return q + "\"";
  }

 private:
  void prefix(const char* key) {
    if (!first_.empty()) {
      if (!first_.back()) out_ += ',';
      first_.back() = false;
      out_ += '\n';
      out_.append(2 * first_.size(), ' ');
    }
    if (key) out_ += quote(key) + ": ";
  }
  JsonWriter& open(const char* key, char bracket) {
    prefix(key);
    out_ += bracket;
    first_.push_back(true);
    return *this;
  }
  JsonWriter& close(char bracket) {
    const bool empty = first_.back();
    first_.pop_back();
    if (!empty) {
      out_ += '\n';
      out_.append(2 * first_.size(), ' ');
    }
    out_ += bracket;
    return *this;
  }

  std::string out_;
  std::vector<bool> first_;  // per open container: no element written yet
};

}  // namespace dhr::bench
