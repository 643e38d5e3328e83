#include "traces/shown_frame.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace dhr {

namespace {

using Json = nlohmann::ordered_json;  // fields in the order written: frame first

Json view_json(const View& v) {
  const Pose& p = v.pose;
  return Json{{"position", {p.position.x, p.position.y, p.position.z}},
              {"orientation", {p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z}},
              {"fov", {v.fov.angle_left, v.fov.angle_right, v.fov.angle_up, v.fov.angle_down}}};
}

// Field access that reports what is wrong instead of throwing.
struct Reader {
  std::string error;

  const Json* field(const Json& object, const char* name, const std::string& where) {
    if (!error.empty()) return nullptr;
    if (!object.is_object()) {
      error = where + ": not an object";
      return nullptr;
    }
    const auto it = object.find(name);
    if (it == object.end()) {
      error = where + ": no \"" + name + "\"";
      return nullptr;
    }
    return &*it;
  }
  std::optional<uint64_t> count(const Json& object, const char* name, const std::string& where) {
    const Json* j = field(object, name, where);
    if (j == nullptr) return std::nullopt;
    if (!j->is_number_unsigned()) {
      error = where + ": \"" + name + "\" is not a non-negative integer";
      return std::nullopt;
    }
    return j->get<uint64_t>();
  }
  std::optional<bool> flag(const Json& object, const char* name, const std::string& where) {
    const Json* j = field(object, name, where);
    if (j == nullptr) return std::nullopt;
    if (!j->is_boolean()) {
      error = where + ": \"" + name + "\" is not true or false";
      return std::nullopt;
    }
    return j->get<bool>();
  }
  std::optional<std::string> text(const Json& object, const char* name, const std::string& where) {
    const Json* j = field(object, name, where);
    if (j == nullptr) return std::nullopt;
    if (!j->is_string()) {
      error = where + ": \"" + name + "\" is not a string";
      return std::nullopt;
    }
    return j->get<std::string>();
  }
  // An array of exactly n finite numbers.
  std::optional<std::vector<double>> numbers(const Json& object, const char* name, size_t n,
                                              const std::string& where) {
    const Json* j = field(object, name, where);
    if (j == nullptr) return std::nullopt;
    if (!j->is_array() || j->size() != n) {
      error = where + ": \"" + name + "\" is not an array of " + std::to_string(n) + " numbers";
      return std::nullopt;
    }
    std::vector<double> out;
    for (const Json& v : *j) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) {
        error = where + ": \"" + name + "\" has a value that is not a finite number";
        return std::nullopt;
      }
      out.push_back(v.get<double>());
    }
    return out;
  }
  std::optional<Extent> extent(const Json& object, const char* name, const std::string& where, uint32_t min) {
    const Json* j = field(object, name, where);
    if (j == nullptr) return std::nullopt;
    if (!j->is_array() || j->size() != 2 || !(*j)[0].is_number_unsigned() || !(*j)[1].is_number_unsigned() ||
        (*j)[0].get<uint64_t>() < min || (*j)[1].get<uint64_t>() < min ||
        (*j)[0].get<uint64_t>() > kMaxImageDimension || (*j)[1].get<uint64_t>() > kMaxImageDimension) {
      error = where + ": \"" + name + "\" is not [width, height] in " + std::to_string(min) + ".." +
              std::to_string(kMaxImageDimension);
      return std::nullopt;
    }
    return Extent{(*j)[0].get<uint32_t>(), (*j)[1].get<uint32_t>()};
  }
};

bool plain_file_name(const std::string& name) {
  if (name.empty() || name.size() > 255 || name.front() == '.') return false;
  for (char c : name) {
    if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20) return false;
  }
  return true;
}

std::optional<ShownEye> parse_eye(Reader& r, const Json& j, const std::string& where) {
  ShownEye eye;
  const auto position = r.numbers(j, "position", 3, where);
  const auto orientation = r.numbers(j, "orientation", 4, where);
  const auto fov = r.numbers(j, "fov", 4, where);
  const auto file = r.text(j, "file", where);
  const auto has = r.flag(j, "has_visibility", where);
  const auto traced_for = r.count(j, "visibility_frame", where);
  const auto age = r.count(j, "age", where);
  const auto complete = r.flag(j, "complete", where);
  if (!r.error.empty()) return std::nullopt;
  eye.view.pose.position = {(*position)[0], (*position)[1], (*position)[2]};
  eye.view.pose.orientation = glm::dquat((*orientation)[0], (*orientation)[1], (*orientation)[2], (*orientation)[3]);
  eye.view.fov = Fov{static_cast<float>((*fov)[0]), static_cast<float>((*fov)[1]), static_cast<float>((*fov)[2]),
                     static_cast<float>((*fov)[3])};
  if (const auto bad = validate_view(eye.view)) {
    r.error = where + ": " + *bad;
    return std::nullopt;
  }
  // The client wrote a normalized orientation: keep its bits (the exact render must use the same view); renormalize
  // only what was edited or written by something else.
  if (std::abs(glm::length(eye.view.pose.orientation) - 1.0) > 1e-12) eye.view.pose = normalized(eye.view.pose);
  if (!plain_file_name(*file)) {
    r.error = where + ": \"file\" must be a plain file name, got \"" + *file + "\"";
    return std::nullopt;
  }
  eye.file = *file;
  eye.has_visibility = *has;
  eye.visibility_frame = *traced_for;
  eye.age = *age;
  eye.complete = *complete;
  return eye;
}

}  // namespace

std::string shown_frame_json(const ShownFrame& f) {
  Json eyes = Json::array();
  for (const ShownEye& e : f.eyes) {
    Json j = view_json(e.view);
    j["file"] = e.file;
    j["has_visibility"] = e.has_visibility;
    j["visibility_frame"] = e.visibility_frame;
    j["age"] = e.age;
    j["complete"] = e.complete;
    eyes.push_back(std::move(j));
  }
  Json out{{"frame", f.frame},
           {"eye_size", {f.eye_size.width, f.eye_size.height}},
           {"render_path", f.render_path},
           {"warp", f.warp},
           {"view", f.view},
           {"scene_time_ns", f.scene_time_ns}};
  out["guard_per_side"] = f.traced ? Json{f.traced->guard.x, f.traced->guard.y} : Json(nullptr);
  if (f.scene_hash) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(*f.scene_hash));
    out["scene_hash"] = hex;  // a string: JSON readers that hold numbers as doubles keep 53 bits only
  } else {
    out["scene_hash"] = nullptr;
  }
  out["eyes"] = std::move(eyes);
  return out.dump();
}

std::optional<ShownFrame> parse_shown_frame(std::string_view line, std::string* out_error) {
  auto fail = [&](const std::string& message) -> std::optional<ShownFrame> {
    if (out_error != nullptr) *out_error = message;
    return std::nullopt;
  };
  const Json j = Json::parse(line.begin(), line.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return fail("not valid JSON");
  Reader r;
  ShownFrame f;
  const auto frame = r.count(j, "frame", "frame");
  const auto eye_size = r.extent(j, "eye_size", "frame", 1);
  const auto path = r.text(j, "render_path", "frame");
  const auto warp = r.text(j, "warp", "frame");
  const auto view = r.text(j, "view", "frame");
  const Json* guard = r.field(j, "guard_per_side", "frame");
  const Json* hash = r.field(j, "scene_hash", "frame");
  const Json* eyes = r.field(j, "eyes", "frame");
  if (!r.error.empty()) return fail(r.error);
  f.frame = *frame;
  f.eye_size = *eye_size;
  if (*path != "forward" && *path != "deferred") return fail("frame: unknown \"render_path\" \"" + *path + "\"");
  if (*warp != "paper" && *warp != "full" && *warp != "edges" && *warp != "edges-depth")
    return fail("frame: unknown \"warp\" \"" + *warp + "\"");
  if (view->empty() || view->size() > 64) return fail("frame: \"view\" must be a short name");
  if (j.contains("scene_time_ns")) {  // absent in lines written before scenes moved: the rest pose
    const Json& t = j["scene_time_ns"];
    if (!t.is_number_integer() || t.get<int64_t>() < 0) return fail("frame: \"scene_time_ns\" is not an integer >= 0");
    f.scene_time_ns = t.get<int64_t>();
  }
  f.render_path = *path;
  f.warp = *warp;
  f.view = *view;
  if (!guard->is_null()) {
    const auto g = r.extent(j, "guard_per_side", "frame", 0);
    if (!g) return fail(r.error);
    if (g->width > 4096 || g->height > 4096) return fail("frame: \"guard_per_side\" is larger than 4096 pixels per side");
    f.traced = TracedFormat{f.eye_size, GuardBand{g->width, g->height}};
  }
  if (!hash->is_null()) {
    const std::string text = hash->is_string() ? hash->get<std::string>() : std::string();
    if (text.empty() || text.size() > 16 || text.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
      return fail("frame: \"scene_hash\" is not null or 1-16 hex digits");
    }
    f.scene_hash = std::stoull(text, nullptr, 16);
  }
  if (!eyes->is_array() || eyes->size() != 2) return fail("frame: \"eyes\" is not an array of two eyes");
  for (size_t e = 0; e < 2; ++e) {
    const auto eye = parse_eye(r, (*eyes)[e], e == 0 ? "left eye" : "right eye");
    if (!eye) return fail(r.error);
    f.eyes[e] = *eye;
  }
  return f;
}

std::optional<std::vector<ShownFrame>> read_shown_frames(const std::string& path, std::string* out_error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (out_error != nullptr) *out_error = path + ": cannot open";
    return std::nullopt;
  }
  std::vector<ShownFrame> frames;
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::string error;
    auto frame = parse_shown_frame(line, &error);
    if (!frame) {
      if (out_error != nullptr) *out_error = path + ":" + std::to_string(number) + ": " + error;
      return std::nullopt;
    }
    frames.push_back(std::move(*frame));
  }
  return frames;
}

}  // namespace dhr
