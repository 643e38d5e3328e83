// LightSlots (scene/light_slots.hpp): many lights in one 32-bit mask, coloured by a world grid.
#include "scene/light_slots.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "visibility/visibility_layout.hpp"

namespace dhr {
namespace {

SceneLight point(glm::vec3 position, float range) {
  SceneLight l;
  l.type = SceneLight::Type::kPoint;
  l.position = position;
  l.range = range;
  return l;
}

// n x n point lights `spacing` apart on the floor plane, each reaching `range`.
std::vector<SceneLight> floor_grid(int n, float spacing, float range) {
  std::vector<SceneLight> lights;
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) lights.push_back(point({x * spacing, 2.0f, z * spacing}, range));
  return lights;
}

TEST(LightSlots, AtMost32LightsAreTheirOwnSlots) {
  std::vector<SceneLight> lights = floor_grid(5, 1.0f, 0.6f);  // 25
  lights[3].radius = 0.05f;                                     // a sphere light: a soft slot
  const LightSlots slots = LightSlots::assign(lights);
  ASSERT_TRUE(slots.is_identity());
  EXPECT_EQ(slots.slot_count(), 25u);
  EXPECT_TRUE(slots.soft_slots()[3]);
  EXPECT_FALSE(slots.soft_slots()[4]);
  for (const glm::dvec3 p : {glm::dvec3(0.0), glm::dvec3(100.0, -5.0, 3.0)}) {
    const uint16_t* row = slots.lights_at(p);
    for (uint32_t i = 0; i < 25; ++i) EXPECT_EQ(row[i], i);
  }
  EXPECT_TRUE(slots.dropped().empty());
}

// The property both ends rely on: wherever a light reaches, its slot holds that light, also at points up to the
// margin away (where the other end may bin the same surface point), and no other light of its slot reaches there.
void expect_slots_hold_their_lights(const std::vector<SceneLight>& lights, const LightSlots& slots, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double jitter = 0.9 * kSlotMarginMm / 1000.0 / std::sqrt(3.0);
  uint32_t checked = 0;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (slots.slot_of(i) == kNoSlotLight) continue;
    const glm::dvec3 c(lights[i].position);
    for (int k = 0; k < 200; ++k) {
      const glm::dvec3 d(unit(rng), unit(rng), unit(rng));
      if (d.x * d.x + d.y * d.y + d.z * d.z > 1.0) continue;
      const glm::dvec3 p = c + d * static_cast<double>(lights[i].range);  // within the range
      const glm::dvec3 q = p + glm::dvec3(unit(rng), unit(rng), unit(rng)) * jitter;  // the other end's binning
      ASSERT_EQ(slots.light_at(slots.slot_of(i), p), i) << "light " << i;
      ASSERT_EQ(slots.light_at(slots.slot_of(i), q), i) << "light " << i << " within the margin";
      for (uint32_t j = 0; j < lights.size(); ++j) {
        if (j == i || slots.slot_of(j) != slots.slot_of(i)) continue;
        const glm::dvec3 e = p - glm::dvec3(lights[j].position);
        ASSERT_GT(std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z), lights[j].range) << "lights " << i << ", " << j;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 0u);
}

TEST(LightSlots, SixtyFourLightsShareSlotsWhereTheyCannotMeet) {
  const std::vector<SceneLight> lights = floor_grid(8, 1.0f, 0.6f);
  const LightSlots slots = LightSlots::assign(lights);
  ASSERT_FALSE(slots.is_identity());
  EXPECT_TRUE(slots.dropped().empty());
  EXPECT_LE(slots.slot_count(), 16u) << slots.describe();
  EXPECT_LE(slots.max_lights_per_cell(), slots.slot_count());
  expect_slots_hold_their_lights(lights, slots, 1);
  // Far from every light, no slot holds one.
  const uint16_t* row = slots.lights_at(glm::dvec3(-50.0, 0.0, 0.0));
  for (uint32_t s = 0; s < slots.slot_count(); ++s) EXPECT_EQ(row[s], kNoSlotLight);
}

TEST(LightSlots, TwoHundredFiftySixLightsFitAndStayDeterministic) {
  std::vector<SceneLight> lights;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> x(0.0f, 6.0f), y(0.3f, 2.6f), z(0.0f, 4.0f);
  for (int i = 0; i < 256; ++i) lights.push_back(point({x(rng), y(rng), z(rng)}, 0.5f));
  const LightSlots slots = LightSlots::assign(lights);
  EXPECT_LE(slots.slot_count(), 32u);
  expect_slots_hold_their_lights(lights, slots, 2);
  EXPECT_EQ(LightSlots::assign(lights), slots);
  EXPECT_TRUE(slots.dropped().empty()) << slots.describe();
}

TEST(LightSlots, LightsWithoutARangeAreGlobal) {
  std::vector<SceneLight> lights = floor_grid(6, 1.0f, 0.6f);  // 36
  SceneLight sun;
  sun.type = SceneLight::Type::kDirectional;
  sun.angle = 0.0093f;
  lights.insert(lights.begin() + 5, sun);
  lights.push_back(point({1.0f, 1.0f, 1.0f}, 0.0f));  // no range: reaches everything
  const LightSlots slots = LightSlots::assign(lights);
  ASSERT_FALSE(slots.is_identity());
  EXPECT_EQ(slots.global_lights(), 2u);
  EXPECT_EQ(slots.slot_of(5), 0u);
  EXPECT_TRUE(slots.soft_slots()[0]);
  EXPECT_EQ(slots.slot_of(37), 1u);
  for (const glm::dvec3 p : {glm::dvec3(2.0, 2.0, 2.0), glm::dvec3(1e4, 0.0, 0.0)}) {
    EXPECT_EQ(slots.light_at(0, p), 5u);
    EXPECT_EQ(slots.light_at(1, p), 37u);
  }
  expect_slots_hold_their_lights(lights, slots, 3);
}

TEST(LightSlots, LightsBeyondThe32BitsAreDroppedAndNamed) {
  // 40 hard lights that all reach one point need 40 slots: 32 fit.
  std::vector<SceneLight> hard(40, point({0.0f, 1.0f, 0.0f}, 1.0f));
  LightSlots slots = LightSlots::assign(hard);
  EXPECT_EQ(slots.slot_count(), 32u);
  ASSERT_EQ(slots.dropped().size(), 8u);
  EXPECT_EQ(slots.dropped().front(), 32u);
  EXPECT_EQ(slots.slot_of(35), kNoSlotLight);
  EXPECT_NE(slots.describe().find("8 left without a slot"), std::string::npos) << slots.describe();
  // Soft lights take 3 bits each: 10 slots.
  std::vector<SceneLight> soft = hard;
  for (SceneLight& l : soft) l.radius = 0.05f;
  slots = LightSlots::assign(soft);
  EXPECT_EQ(slots.slot_count(), 10u);
  EXPECT_EQ(slots.dropped().size(), 30u);
  std::vector<bool> soft_slots = slots.soft_slots();
  bool flags[32] = {};
  for (size_t s = 0; s < soft_slots.size(); ++s) flags[s] = soft_slots[s];
  const VisibilityLayout layout = VisibilityLayout::for_lights(std::span<const bool>(flags, soft_slots.size()));
  EXPECT_EQ(layout.total_bits(), 30u);
  EXPECT_EQ(layout.demoted, 0u);
}

TEST(LightSlots, RefusesWhatItCannotPlaceAndMakesHugeRangesGlobal) {
  std::vector<SceneLight> lights = floor_grid(7, 1.0f, 0.5f);  // 49
  lights[10].position.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(LightSlots::assign(lights), std::invalid_argument);
  lights[10].position.x = 1.0f;
  EXPECT_THROW(LightSlots::assign(std::vector<SceneLight>(kMaxSlotLights + 1, point({0, 0, 0}, 1.0f))),
               std::invalid_argument);
  // A range too large to place (legal in glTF), or infinite, makes the light global instead of refusing the scene.
  for (const float range : {1e30f, std::numeric_limits<float>::infinity()}) {
    lights[11].range = range;
    const LightSlots far = LightSlots::assign(lights);
    EXPECT_EQ(far.global_lights(), 1u);
    EXPECT_EQ(far.slot_of(11), 0u);
  }
  // A NaN point is outside the grid: global slots only.
  lights[11].range = 0.5f;
  const LightSlots slots = LightSlots::assign(lights);
  const uint16_t* row = slots.lights_at(glm::dvec3(std::nan(""), 0.0, 0.0));
  for (uint32_t s = 0; s < slots.slot_count(); ++s) EXPECT_EQ(row[s], kNoSlotLight);
}

}  // namespace
}  // namespace dhr
