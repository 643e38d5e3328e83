// JsonCheck: typed glTF JSON access that records the first problem with its path.
#include "scene_json_check.hpp"

#include <cmath>

namespace dhr::scene_detail {

const char* kind_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::null:
      return "null";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

std::string at(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }
std::string key(const std::string& base, const char* k) { return base.empty() ? k : base + "." + k; }

bool JsonCheck::fail(const std::string& path, const std::string& message) {
  if (error_.empty()) error_ = path + ": " + message;
  return false;
}

namespace {

// The member's address, or null: callers test one pointer, which also keeps GCC's -Wnull-dereference
// from flagging nlohmann's iterator dereferences once inlined.
const Json* find_member(const Json& o, const char* k) {
  if (!o.is_object() || !o.contains(k)) return nullptr;
  return &o.at(k);
}

}  // namespace

const Json* JsonCheck::member(const Json& o, const char* k, const std::string& path, Json::value_t want,
                              bool required) {
  const Json* it = find_member(o, k);
  if (it == nullptr) {
    if (required) fail(key(path, k), "required but missing");
    return nullptr;
  }
  const bool is_number = it->is_number();
  const bool match = want == Json::value_t::number_float ? is_number : it->type() == want;
  if (!match) {
    const char* expected = want == Json::value_t::object    ? "an object"
                           : want == Json::value_t::array   ? "an array"
                           : want == Json::value_t::string  ? "a string"
                           : want == Json::value_t::boolean ? "a boolean"
                                                            : "a number";
    fail(key(path, k), std::string("expected ") + expected + ", got " + kind_name(*it));
    return nullptr;
  }
  return it;
}

bool JsonCheck::as_uint(const Json& v, std::uint64_t* out) {
  if (v.is_number_unsigned()) {
    *out = v.get<std::uint64_t>();
    return true;
  }
  if (v.is_number_integer()) {
    const std::int64_t i = v.get<std::int64_t>();
    if (i < 0) return false;
    *out = static_cast<std::uint64_t>(i);
    return true;
  }
  if (v.is_number_float()) {  // 3.0 is tolerated as 3
    const double d = v.get<double>();
    if (!(d >= 0.0) || d > 9.0e15 || std::floor(d) != d) return false;
    *out = static_cast<std::uint64_t>(d);
    return true;
  }
  return false;
}

bool JsonCheck::uint_member(const Json& o, const char* k, const std::string& path, std::uint64_t* out, bool required,
                            std::uint64_t lo, std::uint64_t hi) {
  const Json* it = find_member(o, k);
  if (it == nullptr) return required ? fail(key(path, k), "required but missing") : true;
  std::uint64_t v = 0;
  if (!as_uint(*it, &v)) {
    return fail(key(path, k),
                std::string("expected a non-negative integer, got ") + (it->is_number() ? it->dump() : kind_name(*it)));
  }
  if (v < lo || v > hi) {
    return fail(key(path, k), "value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
  }
  *out = v;
  return true;
}

bool JsonCheck::index_member(const Json& o, const char* k, const std::string& path, std::size_t count, const char* what,
                             bool required, std::int64_t* out) {
  std::uint64_t v = 0;
  const bool present = o.contains(k);
  if (!uint_member(o, k, path, &v, required)) return false;
  if (!present) return true;
  if (v >= count) {
    return fail(key(path, k), "refers to " + std::string(what) + " " + std::to_string(v) + ", but there are " +
                                  std::to_string(count));
  }
  if (out) *out = static_cast<std::int64_t>(v);
  return true;
}

bool JsonCheck::number_member(const Json& o, const char* k, const std::string& path, double lo, double hi,
                              double* out) {
  const Json* v = member(o, k, path, Json::value_t::number_float);
  if (!v) return error_.empty();
  const double d = v->get<double>();
  if (!std::isfinite(d) || d < lo || d > hi) return fail(key(path, k), "value " + v->dump() + " out of range");
  if (out) *out = d;
  return true;
}

bool JsonCheck::numbers_member(const Json& o, const char* k, const std::string& path, std::size_t n) {
  const Json* v = member(o, k, path, Json::value_t::array);
  if (!v) return error_.empty();
  if (v->size() != n) {
    return fail(key(path, k), "expected " + std::to_string(n) + " numbers, got " + std::to_string(v->size()));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(*v)[i].is_number())
      return fail(at(key(path, k), i), std::string("expected a number, got ") + kind_name((*v)[i]));
    if (!std::isfinite((*v)[i].get<double>())) return fail(at(key(path, k), i), "not finite");
  }
  return true;
}

bool JsonCheck::common(const Json& o, const std::string& path) {
  member(o, "name", path, Json::value_t::string);
  if (const Json* ext = member(o, "extensions", path, Json::value_t::object)) {
    for (auto it = ext->begin(); it != ext->end(); ++it) {
      if (!it->is_object()) {
        return fail(key(path, "extensions") + "." + it.key(), std::string("expected an object, got ") + kind_name(*it));
      }
    }
  }
  return error_.empty();
}

bool JsonCheck::array_of_objects(const Json& o, const char* k, const std::string& path, std::vector<const Json*>* out) {
  out->clear();
  const Json* arr = member(o, k, path, Json::value_t::array);
  if (!arr) return error_.empty();
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const Json& item = (*arr)[i];
    if (!item.is_object()) return fail(at(key(path, k), i), std::string("expected an object, got ") + kind_name(item));
    if (!common(item, at(key(path, k), i))) return false;
    out->push_back(&item);
  }
  return true;
}

}  // namespace dhr::scene_detail
