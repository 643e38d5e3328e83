// Small pieces of the scene API: bounds, UV transform, summary, and the loader's warning collector.
#include "scene/scene.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <glm/geometric.hpp>

#include "scene_internal.hpp"

namespace dhr {

void SceneBounds::extend(const glm::vec3& p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

void SceneBounds::extend(const SceneBounds& other) {
  if (other.empty()) return;
  extend(other.min);
  extend(other.max);
}

glm::vec3 SceneBounds::center() const { return empty() ? glm::vec3(0.0f) : 0.5f * (min + max); }

glm::vec3 SceneBounds::size() const { return empty() ? glm::vec3(0.0f) : max - min; }

float SceneBounds::diagonal() const { return glm::length(size()); }

glm::vec2 UvTransform::apply(const glm::vec2& uv) const {
  // KHR_texture_transform: T * R * S with R = [cos sin; -sin cos] (row-major as the extension writes it).
  const float c = std::cos(rotation);
  const float s = std::sin(rotation);
  const glm::vec2 scaled = uv * scale;
  return offset + glm::vec2(c * scaled.x + s * scaled.y, -s * scaled.x + c * scaled.y);
}

std::string scene_summary(const Scene& scene) {
  const glm::vec3 lo = scene.bounds.empty() ? glm::vec3(0.0f) : scene.bounds.min;
  const glm::vec3 hi = scene.bounds.empty() ? glm::vec3(0.0f) : scene.bounds.max;
  char line[512];
  std::snprintf(line, sizeof line,
                "%s: %llu triangles, %zu meshes, %zu materials, %zu images, %zu lights%s, "
                "bounds (%.3g, %.3g, %.3g)..(%.3g, %.3g, %.3g), %zu warnings",
                scene.source.c_str(), static_cast<unsigned long long>(scene.triangle_count), scene.meshes.size(),
                scene.materials.size(), scene.images.size(), scene.lights.size(),
                scene.default_lights ? " (default rig)" : "", static_cast<double>(lo.x), static_cast<double>(lo.y),
                static_cast<double>(lo.z), static_cast<double>(hi.x), static_cast<double>(hi.y),
                static_cast<double>(hi.z), scene.warnings.size());
  return line;
}

namespace scene_detail {

std::string format(const char* fmt, ...) {
  char buffer[1024];
  va_list args;
  va_start(args, fmt);
  const int n = std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  if (n < 0) return fmt;
  return std::string(buffer,
                     static_cast<std::size_t>(n) < sizeof buffer ? static_cast<std::size_t>(n) : sizeof buffer - 1);
}

void WarningSink::add(std::string message) {
  if (messages_.size() < cap_) {
    messages_.push_back(std::move(message));
  } else {
    ++dropped_;
  }
}

void WarningSink::add_lines(const std::string& text) {
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    if (end > begin) add(text.substr(begin, end - begin));
    begin = end + 1;
  }
}

std::vector<std::string> WarningSink::take() {
  std::vector<std::string> out = std::move(messages_);
  if (dropped_ > 0) out.push_back("... and " + std::to_string(dropped_) + " more warnings");
  messages_.clear();
  dropped_ = 0;
  return out;
}

}  // namespace scene_detail
}  // namespace dhr
