#include "client_bench_configs.hpp"

#include <cmath>
#include <cstdio>

#include "cli/exit_codes.hpp"
#include "vk/context.hpp"

namespace dhr::bench {

Config single_eye_config(const vk::Context& context, std::string name,
                         std::function<void(VkCommandBuffer, uint32_t)> record,
                         std::function<std::optional<double>()> time_ms) {
  return Config{std::move(name),
                [&context, record = std::move(record), time_ms = std::move(time_ms)](uint32_t i) {
                  context.submit_and_wait([&](VkCommandBuffer cmd) { record(cmd, i); });
                  const std::optional<double> ms = time_ms();
                  return ms ? std::vector<double>{*ms} : std::vector<double>{};
                },
                {}};
}

void measure(uint32_t warmup, uint32_t frames, std::vector<Config>& configs) {
  for (uint32_t i = 0; i < warmup + frames; ++i) {
    for (Config& c : configs) {
      const std::vector<double> ms = c.run(i);
      if (i >= warmup) c.samples.insert(c.samples.end(), ms.begin(), ms.end());
    }
    if ((i + 1) % 10 == 0) std::fprintf(stderr, "client_bench: frame %u of %u\n", i + 1, warmup + frames);
  }
}

std::optional<Extent> parse_size(const std::string& text) {
  unsigned w = 0, h = 0;
  char x = 0;
  int used = 0;
  if (std::sscanf(text.c_str(), "%u%c%u%n", &w, &x, &h, &used) != 3 || (x != 'x' && x != 'X') ||
      static_cast<size_t>(used) != text.size() || text[0] == '-') {
    return std::nullopt;
  }
  if (w == 0 || h == 0 || w > 8192 || h > 8192) return std::nullopt;
  return Extent{w, h};
}

void add_lights(Scene& scene, uint32_t count) {
  std::vector<SceneLight> sources;
  for (const SceneLight& l : scene.lights)
    if (l.type != SceneLight::Type::kDirectional) sources.push_back(l);
  if (sources.empty()) throw cli::InputError("--lights: the scene has no point or spot light to copy");
  const size_t original = scene.lights.size();
  for (size_t i = original; i < count; ++i) {
    SceneLight l = sources[(i - original) % sources.size()];
    // A copy of a rect or disk light is a point light of its peak intensity (nits x area candela); copies are
    // punctual (they only add shadow-map load).
    if (l.type == SceneLight::Type::kRect || l.type == SceneLight::Type::kDisk) l.intensity *= l.area();
    l.type = SceneLight::Type::kPoint;
    l.radius = l.angle = l.width = l.height = 0.0f;
    const double a = 2.399963 * static_cast<double>(i);  // golden angle: spread around the original
    const double r = 0.25 + 0.35 * static_cast<double>((i * 7) % 10) / 10.0;
    l.position += glm::vec3(static_cast<float>(r * std::cos(a)), -0.1f * static_cast<float>(i % 3),
                            static_cast<float>(r * std::sin(a)));
    l.intensity *= static_cast<float>(original) / static_cast<float>(count);
    scene.lights.push_back(l);
  }
}

}  // namespace dhr::bench
