// Typed access to glTF JSON for the scene validator (shared/scene/src/scene_validate*.cpp only): every getter
// records the first problem with its JSON path ("meshes[0].primitives: expected an array, got ...").
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dhr::scene_detail {

using Json = nlohmann::json;

const char* kind_name(const Json& v);                     // "an object", "a number", ...
std::string at(const std::string& base, std::size_t i);   // base[i]
std::string key(const std::string& base, const char* k);  // base.k

class JsonCheck {
 public:
  bool ok() const { return error_.empty(); }

 protected:
  // Records `path: message` unless a problem was recorded already; returns false.
  bool fail(const std::string& path, const std::string& message);
  // Member `k` of `o` when present with the right kind (number_float stands for any number); nullptr
  // when absent or of the wrong kind (error recorded, or "required but missing").
  const Json* member(const Json& o, const char* k, const std::string& path, Json::value_t want, bool required = false);
  // Non-negative integers (3.0 is tolerated as 3).
  static bool as_uint(const Json& v, std::uint64_t* out);
  // Non-negative integer member in [lo, hi]; `out` untouched when absent.
  bool uint_member(const Json& o, const char* k, const std::string& path, std::uint64_t* out, bool required,
                   std::uint64_t lo = 0, std::uint64_t hi = ~0ull);
  // Index into an array of `count` items (`what` names it in the message).
  bool index_member(const Json& o, const char* k, const std::string& path, std::size_t count, const char* what,
                    bool required, std::int64_t* out = nullptr);
  // Finite number in [lo, hi]; `out` untouched when absent.
  bool number_member(const Json& o, const char* k, const std::string& path, double lo, double hi,
                     double* out = nullptr);
  // Array of exactly n finite numbers.
  bool numbers_member(const Json& o, const char* k, const std::string& path, std::size_t n);
  // `name` must be a string; `extensions` an object of objects.
  bool common(const Json& o, const std::string& path);
  // An array of objects (absent = empty), each passing common().
  bool array_of_objects(const Json& o, const char* k, const std::string& path, std::vector<const Json*>* out);

  std::string error_;
};

}  // namespace dhr::scene_detail
