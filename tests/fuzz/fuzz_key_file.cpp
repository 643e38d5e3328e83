// Fuzz target: secure::parse_key on arbitrary text (a key file). Properties: no crash or sanitizer report;
// a rejection always says why; an accepted key formats to text that parses back to the same key.
#include "fuzz_support.hpp"
#include "secure/key.hpp"

#include <algorithm>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const std::optional<dhr::secure::Key> key = dhr::secure::parse_key(text, &error);
  if (!key) {
    DHR_FUZZ_CHECK_MSG(!error.empty(), "a rejection without a reason");
    return 0;
  }
  const std::optional<dhr::secure::Key> again = dhr::secure::parse_key(dhr::secure::format_key(*key), &error);
  DHR_FUZZ_CHECK(again.has_value());
  DHR_FUZZ_CHECK(std::equal(key->data(), key->data() + dhr::secure::kKeySize, again->data()));
  return 0;
}
