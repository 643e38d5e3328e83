// Light spec strings, the default light rig, and replacing a scene's lights.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <string>

#include "scene/scene.hpp"

namespace {

using dhr::SceneLight;

TEST(SceneLightSpec, ParsesPointLightsWithAndWithoutRange) {
  std::string error;
  auto light = dhr::parse_light_spec("point:1,2.5,-3:1,0.5,0.25:40", &error);
  ASSERT_TRUE(light) << error;
  EXPECT_EQ(light->type, SceneLight::Type::kPoint);
  EXPECT_EQ(light->position, glm::vec3(1.0f, 2.5f, -3.0f));
  EXPECT_EQ(light->color, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(light->intensity, 40.0f);
  EXPECT_FLOAT_EQ(light->range, 0.0f);
  EXPECT_FALSE(light->is_default);
  light = dhr::parse_light_spec(" point: 0, 3, 0 : 1,1,1 : 12.5 : 8 ", &error);
  ASSERT_TRUE(light) << error;
  EXPECT_FLOAT_EQ(light->range, 8.0f);
  EXPECT_FLOAT_EQ(light->intensity, 12.5f);
}

TEST(SceneLightSpec, ParsesDirectionalAndSpotLightsAndNormalizesDirections) {
  std::string error;
  auto dir = dhr::parse_light_spec("dir:0,-2,0:1,1,0.9:3", &error);
  ASSERT_TRUE(dir) << error;
  EXPECT_EQ(dir->type, SceneLight::Type::kDirectional);
  EXPECT_EQ(dir->direction, glm::vec3(0.0f, -1.0f, 0.0f));
  EXPECT_TRUE(dhr::parse_light_spec("directional:1,-1,0:1,1,1:2", &error)) << error;
  auto spot = dhr::parse_light_spec("spot:0,3,0:0,-1,0:1,1,1:100:20,30:12", &error);
  ASSERT_TRUE(spot) << error;
  EXPECT_EQ(spot->type, SceneLight::Type::kSpot);
  EXPECT_NEAR(spot->inner_cone, 20.0 * M_PI / 180.0, 1e-6);
  EXPECT_NEAR(spot->outer_cone, 30.0 * M_PI / 180.0, 1e-6);
  EXPECT_FLOAT_EQ(spot->range, 12.0f);
}

TEST(SceneLightSpec, RejectsMalformedSpecsWithAReason) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "unknown light type"},
      {"area:0,0,0:1,1,1:1", "unknown light type \"area\""},
      {"point:0,0:1,1,1:1", "position: expected 3 comma-separated numbers"},
      {"point:0,0,0:1,1,1", "expected point:x,y,z:r,g,b:intensity[:range]"},
      {"point:0,0,0:1,1,1:1:2:3", "expected point"},
      {"point:0,x,0:1,1,1:1", "\"x\" is not a finite number"},
      {"point:0,0,0:1,1,1:nan", "is not a finite number"},
      {"point:0,0,0:1,1,1:inf", "is not a finite number"},
      {"point:0,0,0:1,1,1:1e39", "is not a finite number"},
      {"point:0,0,0:1,1,1:-2", "negative intensity"},
      {"point:0,0,0:-1,1,1:2", "negative colour"},
      {"point:0,0,0:1,1,1:2:-1", "negative range"},
      {"point:0,0,0:1,1,1:2 x", "is not a finite number"},
      {"dir:0,0,0:1,1,1:1", "direction must not be zero"},
      {"dir:0,-1,0:1,1,1:1:5", "expected dir:dx,dy,dz:r,g,b:intensity"},
      {"spot:0,3,0:0,-1,0:1,1,1:100:30,20", "inner cone < outer cone"},
      {"spot:0,3,0:0,-1,0:1,1,1:100:10,95", "inner cone < outer cone"},
  };
  for (const auto& [spec, phrase] : cases) {
    std::string error;
    EXPECT_FALSE(dhr::parse_light_spec(spec, &error)) << spec;
    EXPECT_NE(error.find(phrase), std::string::npos) << spec << " -> " << error;
    EXPECT_NE(error.find("light spec"), std::string::npos) << error;
  }
  EXPECT_FALSE(dhr::parse_light_spec("bogus", nullptr));  // no error pointer: still no crash
}

TEST(SceneLightSpec, FormatRoundTrips) {
  for (const char* spec : {"point:1,2,3:0.5,0.25,1:40", "point:1,2,3:1,1,1:40:7.5", "dir:0,-1,0:1,0.9,0.8:2",
                           "spot:0,3,0:0,-1,0:1,1,1:100:20,30:12"}) {
    std::string error;
    auto light = dhr::parse_light_spec(spec, &error);
    ASSERT_TRUE(light) << error;
    auto again = dhr::parse_light_spec(dhr::format_light_spec(*light), &error);
    ASSERT_TRUE(again) << error;
    EXPECT_EQ(again->type, light->type);
    EXPECT_EQ(again->position, light->position);
    EXPECT_EQ(again->direction, light->direction);
    EXPECT_EQ(again->color, light->color);
    EXPECT_EQ(again->intensity, light->intensity);
    EXPECT_EQ(again->range, light->range);
    EXPECT_NEAR(again->inner_cone, light->inner_cone, 1e-6);
    EXPECT_NEAR(again->outer_cone, light->outer_cone, 1e-6);
  }
}

TEST(SceneLightSpec, ParsesListsAndEnforcesTheLimit) {
  std::string error;
  auto lights = dhr::parse_light_specs("point:0,2,0:1,1,1:10; dir:0,-1,0:1,1,1:1;", &error);
  ASSERT_TRUE(lights) << error;
  EXPECT_EQ(lights->size(), 2u);
  EXPECT_FALSE(dhr::parse_light_specs("point:0,2,0:1,1,1:10;point:oops", &error));
  EXPECT_NE(error.find("point:oops"), std::string::npos) << error;
  std::string many;
  for (int i = 0; i < 257; ++i) many += "point:0,2,0:1,1,1:1;";
  EXPECT_FALSE(dhr::parse_light_specs(many, &error));
  EXPECT_NE(error.find("too many lights: 257 (at most 256)"), std::string::npos) << error;
}

TEST(SceneDefaultRig, IsThreeDocumentedLightsInsideTheBox) {
  dhr::SceneBounds room;
  room.extend(glm::vec3(-3.0f, 0.0f, -2.0f));
  room.extend(glm::vec3(3.0f, 2.8f, 2.0f));
  const auto rig = dhr::make_default_light_rig(room);
  ASSERT_EQ(rig.size(), 3u);
  EXPECT_EQ(rig[0].type, SceneLight::Type::kPoint);
  EXPECT_EQ(rig[1].type, SceneLight::Type::kPoint);
  EXPECT_EQ(rig[2].type, SceneLight::Type::kDirectional);
  const glm::vec3 c = room.center();
  for (const auto& l : rig) {
    EXPECT_TRUE(l.is_default);
    EXPECT_FALSE(dhr::validate_light(l).has_value());
    if (l.type != SceneLight::Type::kPoint) continue;
    // Inside the box, so closed rooms with inward-facing walls are lit from inside.
    EXPECT_GT(l.position.x, room.min.x);
    EXPECT_LT(l.position.x, room.max.x);
    EXPECT_GT(l.position.y, room.min.y);
    EXPECT_LT(l.position.y, room.max.y);
    EXPECT_GT(l.position.z, room.min.z);
    EXPECT_LT(l.position.z, room.max.z);
  }
  // Key: high and in front (+Z), irradiance 3 at the centre; fill: irradiance 1; sun from above.
  EXPECT_GT(rig[0].position.y, c.y);
  EXPECT_GT(rig[0].position.z, c.z);
  const glm::vec3 d0 = rig[0].position - c;
  EXPECT_NEAR(rig[0].intensity / glm::dot(d0, d0), 3.0f, 1e-4f);
  const glm::vec3 d1 = rig[1].position - c;
  EXPECT_NEAR(rig[1].intensity / glm::dot(d1, d1), 1.0f, 1e-4f);
  EXPECT_LT(rig[1].position.x * rig[0].position.x, 0.0f);  // opposite sides
  EXPECT_LT(rig[2].direction.y, -0.5f);
  EXPECT_NEAR(glm::length(rig[2].direction), 1.0f, 1e-6f);
}

TEST(SceneDefaultRig, HandlesEmptyAndFlatBoxes) {
  for (const auto& rig : {dhr::make_default_light_rig(dhr::SceneBounds{}),
                          dhr::make_default_light_rig(dhr::SceneBounds{glm::vec3(0.0f), glm::vec3(0.0f)})}) {
    ASSERT_EQ(rig.size(), 3u);
    EXPECT_NE(rig[0].position, rig[1].position);
    for (const auto& l : rig) EXPECT_FALSE(dhr::validate_light(l).has_value()) << *dhr::validate_light(l);
  }
}

TEST(SceneSetLights, ReplacesLightsOrExplainsWhyNot) {
  dhr::Scene scene;
  scene.lights = dhr::make_default_light_rig(dhr::SceneBounds{});
  scene.default_lights = true;
  std::string error;
  auto lights = dhr::parse_light_specs("point:0,2,0:1,1,1:10", &error);
  ASSERT_TRUE(lights) << error;
  EXPECT_FALSE(dhr::set_scene_lights(scene, *lights).has_value());
  EXPECT_EQ(scene.lights.size(), 1u);
  EXPECT_FALSE(scene.default_lights);
  std::vector<SceneLight> too_many(dhr::kMaxSceneLights + 1, (*lights)[0]);
  auto problem = dhr::set_scene_lights(scene, too_many);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("too many lights"), std::string::npos);
  SceneLight bad = (*lights)[0];
  bad.intensity = NAN;
  problem = dhr::set_scene_lights(scene, {bad});
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("non-finite"), std::string::npos);
  EXPECT_EQ(scene.lights.size(), 1u);  // unchanged on error
  EXPECT_STREQ(dhr::light_type_name(SceneLight::Type::kSpot), "spot");
}

}  // namespace
