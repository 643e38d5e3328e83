#include "bench_lights.hpp"

#include <cmath>
#include <random>
#include <string>

#include "visibility/visibility.hpp"

namespace dhr::bench {
namespace {

// Beyond kMaxLights lights: the share of the bounding volume they fill (0.8 x 0.8 x 0.8 of its extent) and how many
// of them reach a point of it on average.
constexpr double kManyLightsVolumeShare = 0.8 * 0.8 * 0.8;
constexpr double kManyLightsReach = 6.0;

}  // namespace

double default_bench_light_range(const Scene& scene, uint32_t total) {
  if (total <= kMaxLights) return 0.0;
  const glm::dvec3 e = glm::dvec3(scene.bounds.max) - glm::dvec3(scene.bounds.min);
  const double volume = kManyLightsVolumeShare * e.x * e.y * e.z;  // where add_bench_lights puts them
  const double r = std::cbrt(kManyLightsReach * volume / (4.0 / 3.0 * 3.14159265358979 * total));
  return std::round(r * 100.0) / 100.0;
}

void add_bench_lights(Scene& scene, uint32_t total, double range_m) {
  const SceneBounds& b = scene.bounds;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(0.1f, 0.9f);
  while (scene.lights.size() < total) {
    SceneLight l;
    l.name = "bench light " + std::to_string(scene.lights.size());
    // One draw per statement, z first: the order x86-64's GCC evaluated them in as a call's arguments (which
    // C++ leaves unspecified, and aarch64's GCC takes left to right), so the lights measured so far stay.
    // Up to kMaxLights lights hang in the upper part (0.6-0.9 of the height; the runs of before light slots); more
    // fill the room's height (0.1-0.9), so that they light the floor and the furniture too.
    const float z = u(rng), y = u(rng), x = u(rng);
    const float height = total > kMaxLights ? 0.1f + (y - 0.1f) : 0.6f + 0.3f * y;
    l.position = glm::vec3(b.min.x + x * (b.max.x - b.min.x), b.min.y + height * (b.max.y - b.min.y),
                           b.min.z + z * (b.max.z - b.min.z));
    l.intensity = 20.0f;
    l.range = static_cast<float>(range_m);
    scene.lights.push_back(l);
  }
}

}  // namespace dhr::bench
