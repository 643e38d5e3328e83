// Lights with an extent from small glTF files written here: EXT_lights_area rect and disk lights (placement,
// node scale, defaults), extras.radius / extras.angle, and what each bad value costs (a warning naming the light;
// the extent ignored or the area light skipped; never a failed load).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.hpp"

namespace {

using json = nlohmann::json;
using Type = dhr::SceneLight::Type;

const double kHalfSqrt2 = std::sqrt(0.5);
// -90 degrees about X: the node's -Z (where lights shine) points down (-Y), its +Y points to -Z.
const json kFacingDown = {-kHalfSqrt2, 0, 0, kHalfSqrt2};

// A glTF document with only lights: nodes are roots of scene 0 in the order they are added.
struct LightsGltf {
  json doc = {{"asset", {{"version", "2.0"}}}, {"nodes", json::array()}};

  void punctual(json light) { doc["extensions"]["KHR_lights_punctual"]["lights"].push_back(std::move(light)); }
  void area(json light) { doc["extensions"]["EXT_lights_area"]["lights"].push_back(std::move(light)); }
  void node(json n) { doc["nodes"].push_back(std::move(n)); }
  void punctual_node(int light, json n = json::object()) {
    n["extensions"]["KHR_lights_punctual"]["light"] = light;
    node(std::move(n));
  }
  void area_node(json light, json n = json::object()) {
    n["extensions"]["EXT_lights_area"]["light"] = std::move(light);
    node(std::move(n));
  }
  dhr::SceneLoadResult load() {
    json roots = json::array();
    for (std::size_t i = 0; i < doc["nodes"].size(); ++i) roots.push_back(i);
    doc["scenes"] = json::array({{{"nodes", roots}}});
    dhr::SceneLoadOptions options;
    options.default_lights_when_none = false;  // what the file gives, nothing else
    const std::string text = doc.dump();
    return dhr::load_scene_from_memory(text.data(), text.size(), ".", "lights.gltf", options);
  }
};

bool has_warning(const dhr::Scene& scene, const std::string& phrase) {
  for (const auto& w : scene.warnings) {
    if (w.find(phrase) != std::string::npos) return true;
  }
  return false;
}

std::string all_warnings(const dhr::Scene& scene) {
  std::string out;
  for (const auto& w : scene.warnings) out += w + "\n";
  return out;
}

// The warnings about lights: all but the one every light-only file gets.
std::string light_warnings(const dhr::Scene& scene) {
  std::string out;
  for (const auto& w : scene.warnings)
    if (w != "the scene has no triangles") out += w + "\n";
  return out;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(SceneAreaLights, RectAndDiskFollowTheirNodes) {
  LightsGltf g;
  g.doc["extensionsUsed"] = {"EXT_lights_area"};
  g.doc["extensionsRequired"] = {"EXT_lights_area"};  // implemented, so a file may require it
  g.area({{"name", "panel"}, {"type", "rect"}, {"color", {1, 0.5, 0.25}}, {"intensity", 180}, {"size", 0.4},
          {"rect", {{"aspect", 2.5}}}});
  g.area({{"type", "disk"}, {"intensity", 90}, {"size", 0.6}});
  g.area({{"type", "rect"}});  // every default: 1000 nits, 1 x 1 m
  g.area_node(0, {{"translation", {-1, 2.55, -0.35}}, {"rotation", kFacingDown}});
  g.area_node(1, {{"translation", {1.4, 2.55, 0.75}}, {"rotation", kFacingDown}});
  g.area_node(2);
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 3u) << all_warnings(*r.scene);
  const dhr::SceneLight& rect = lights[0];
  EXPECT_EQ(rect.type, Type::kRect);
  EXPECT_EQ(rect.name, "panel");
  expect_near(rect.position, {-1, 2.55f, -0.35f});
  expect_near(rect.direction, {0, -1, 0});
  expect_near(rect.tangent, {1, 0, 0});
  expect_near(rect.bitangent, {0, 0, -1});
  EXPECT_FLOAT_EQ(rect.width, 1.0f);  // aspect x size
  EXPECT_FLOAT_EQ(rect.height, 0.4f);
  EXPECT_FLOAT_EQ(rect.intensity, 180.0f);  // nits, as the file
  expect_near(rect.color, {1, 0.5f, 0.25f});
  EXPECT_NEAR(rect.area(), 0.4f, 1e-6f);
  EXPECT_TRUE(rect.has_extent());
  EXPECT_FALSE(dhr::validate_light(rect).has_value());
  const dhr::SceneLight& disk = lights[1];
  EXPECT_EQ(disk.type, Type::kDisk);
  EXPECT_EQ(disk.name, "area_light1");
  EXPECT_FLOAT_EQ(disk.width, 0.6f);  // diameter
  EXPECT_FLOAT_EQ(disk.height, 0.6f);
  EXPECT_NEAR(disk.area(), 0.25 * M_PI * 0.36, 1e-6);
  EXPECT_FALSE(dhr::validate_light(disk).has_value());
  EXPECT_FLOAT_EQ(lights[2].intensity, 1000.0f);
  EXPECT_FLOAT_EQ(lights[2].width, 1.0f);
  EXPECT_FLOAT_EQ(lights[2].height, 1.0f);
  expect_near(lights[2].direction, {0, 0, -1});
  EXPECT_EQ(light_warnings(*r.scene), "");
}

// PR 2525: the size is scaled by the largest absolute component of the node's world scale, uniformly.
TEST(SceneAreaLights, TheNodesLargestWorldScaleScalesTheSize) {
  LightsGltf g;
  g.area({{"type", "rect"}, {"size", 0.5}, {"rect", {{"aspect", 2}}}});
  g.node({{"scale", {1, 2, 1}}, {"children", {1}}});
  g.area_node(0, {{"scale", {1, 1.5, -1}}});  // world scale (1, 3, -1): 3
  g.doc["scenes"] = json::array({{{"nodes", {0}}}});
  const std::string text = g.doc.dump();
  auto r = dhr::load_scene_from_memory(text.data(), text.size(), ".", "scaled.gltf");
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->lights.size(), 1u);
  EXPECT_FLOAT_EQ(r.scene->lights[0].height, 1.5f);
  EXPECT_FLOAT_EQ(r.scene->lights[0].width, 3.0f);
  EXPECT_NEAR(glm::length(r.scene->lights[0].tangent), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(r.scene->lights[0].bitangent), 1.0f, 1e-6f);
}

TEST(SceneAreaLights, SphereAndSunExtentsComeFromExtras) {
  LightsGltf g;
  g.punctual({{"type", "point"}, {"name", "bulb"}, {"intensity", 8}, {"extras", {{"radius", 0.06}}}});
  g.punctual({{"type", "directional"}, {"name", "sun"}, {"intensity", 6}, {"extras", {{"angle", 0.0093}}}});
  g.punctual({{"type", "spot"}, {"spot", json::object()}, {"extras", {{"radius", 0}, {"note", "unrelated"}}}});
  g.punctual_node(0, {{"scale", {10, 10, 10}}});  // punctual lights ignore node scale, so does the radius
  g.punctual_node(1);
  g.punctual_node(2);
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0].type, Type::kPoint);
  EXPECT_FLOAT_EQ(lights[0].radius, 0.06f);
  EXPECT_EQ(lights[1].type, Type::kDirectional);
  EXPECT_FLOAT_EQ(lights[1].angle, 0.0093f);
  EXPECT_FALSE(lights[2].has_extent());  // radius 0: punctual, as asked
  for (const auto& l : lights) EXPECT_FALSE(dhr::validate_light(l).has_value()) << l.name;
  EXPECT_EQ(light_warnings(*r.scene), "");
}

// A bad extent on a punctual light costs the extent (the light stays punctual), with a warning naming it.
TEST(SceneAreaLights, BadExtrasAreIgnoredWithAWarning) {
  LightsGltf g;
  const json bad_radii[] = {-0.1, "0.06", nullptr /* what writers make of NaN */, 1000.0};
  for (const json& radius : bad_radii) g.punctual({{"type", "point"}, {"extras", {{"radius", radius}}}});
  g.punctual({{"type", "directional"}, {"name", "wide_sun"}, {"extras", {{"angle", 0.7}}}});
  g.punctual({{"type", "directional"}, {"name", "sun_with_radius"}, {"extras", {{"radius", 0.1}}}});
  g.punctual({{"type", "spot"}, {"name", "spot_with_angle"}, {"spot", json::object()}, {"extras", {{"angle", 0.01}}}});
  for (int i = 0; i < 7; ++i) g.punctual_node(i);
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->lights.size(), 7u);
  for (const auto& l : r.scene->lights) {
    EXPECT_FALSE(l.has_extent()) << l.name;
    EXPECT_FALSE(dhr::validate_light(l).has_value()) << l.name;
  }
  const std::string w = all_warnings(*r.scene);
  EXPECT_TRUE(has_warning(*r.scene, "light 0 (''): extras.radius -0.1 is not a number of metres")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 1 (''): extras.radius \"0.06\"")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 2 (''): extras.radius null")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 3 (''): extras.radius 1000")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "the light stays punctual")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 4 ('wide_sun'): extras.angle 0.7 is not an angular diameter")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 5 ('sun_with_radius'): extras.radius is for point and spot")) << w;
  EXPECT_TRUE(has_warning(*r.scene, "light 6 ('spot_with_angle'): extras.angle is for directional")) << w;
}

// A bad area light definition costs that light, with a warning naming it and what is wrong.
TEST(SceneAreaLights, BadAreaLightsAreSkippedWithAWarning) {
  LightsGltf g;
  g.area({{"name", "zero"}, {"type", "rect"}, {"size", 0}});
  g.area({{"name", "negative"}, {"type", "disk"}, {"size", -1}});
  g.area({{"name", "nan"}, {"type", "disk"}, {"size", nullptr}});  // NaN, as JSON writers emit it
  g.area({{"name", "huge"}, {"type", "rect"}, {"size", 1e9}});
  g.area({{"name", "too_wide"}, {"type", "rect"}, {"size", 50}, {"rect", {{"aspect", 3}}}});  // 150 x 50 m
  g.area({{"name", "flat"}, {"type", "rect"}, {"rect", {{"aspect", 0}}}});
  g.area({{"name", "ball"}, {"type", "sphere"}});
  g.area({{"name", "untyped"}});
  g.area({{"name", "dark"}, {"type", "disk"}, {"intensity", -5}});
  g.area({{"name", "odd_colour"}, {"type", "disk"}, {"color", {1, 1}}});
  g.area({{"name", "good"}, {"type", "disk"}});
  for (int i = 0; i < 11; ++i) g.area_node(i);
  g.area_node(11);     // no light 11
  g.area_node("one");  // not an index
  g.area_node(10, {{"scale", {0, 0, 0}}});
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->lights.size(), 1u) << all_warnings(*r.scene);
  EXPECT_EQ(r.scene->lights[0].name, "good");
  const std::string w = all_warnings(*r.scene);
  for (const char* phrase : {"light 0 ('zero'): size 0 is not a positive number; the light is skipped",
                             "light 1 ('negative'): size -1 is not a positive number",
                             "light 2 ('nan'): size null is not a positive number",
                             "light 3 ('huge')", "light 4 ('too_wide')", "larger than 100 m; the light is skipped",
                             "light 5 ('flat'): rect.aspect 0 is not a positive number",
                             "light 6 ('ball'): unknown type \"sphere\" (rect or disk)",
                             "light 7 ('untyped'): unknown type null",
                             "light 8 ('dark'): intensity -5 is not a luminance",
                             "light 9 ('odd_colour'): color is not 3 finite",
                             "nodes[11]: EXT_lights_area light 11 does not exist (the file defines 11); ignored",
                             "nodes[12]: EXT_lights_area light \"one\" does not exist",
                             "nodes[13]: EXT_lights_area light 10 ('good'): its world size is zero"}) {
    EXPECT_TRUE(has_warning(*r.scene, phrase)) << phrase << "\n" << w;
  }
}

// NaN and Infinity are not JSON: such a file is refused with a parse error (never a crash, never a default).
TEST(SceneAreaLights, ANanLiteralIsAJsonError) {
  LightsGltf g;
  g.area({{"type", "disk"}, {"size", 1.5}});
  g.area_node(0);
  g.doc["scenes"] = json::array({{{"nodes", {0}}}});
  std::string text = g.doc.dump();
  const std::size_t at = text.find("1.5");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 3, "NaN");
  auto r = dhr::load_scene_from_memory(text.data(), text.size(), ".", "nan.gltf");
  EXPECT_FALSE(r);
  EXPECT_NE(r.error.find("nan.gltf"), std::string::npos) << r.error;
}

TEST(SceneAreaLights, AMalformedRootExtensionIsNamed) {
  LightsGltf g;
  g.doc["extensions"]["EXT_lights_area"]["lights"] = "none";
  g.area_node(0);
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  EXPECT_TRUE(r.scene->lights.empty());
  EXPECT_TRUE(has_warning(*r.scene, "EXT_lights_area: \"lights\" is \"none\", not an array")) << all_warnings(*r.scene);
  EXPECT_TRUE(has_warning(*r.scene, "nodes[0]: EXT_lights_area light 0 does not exist"));
}

// Area lights take shadow-mask bits like any other light: the first 32 in node order are kept.
TEST(SceneAreaLights, AreaLightsCountTowardTheLightLimit) {
  LightsGltf g;
  g.punctual({{"type", "point"}});
  g.area({{"type", "disk"}, {"size", 0.2}});
  for (int i = 0; i < 130; ++i) {
    g.punctual_node(0, {{"translation", {i, 0, 0}}});
    g.area_node(0, {{"translation", {i, 1, 0}}});
  }
  auto r = g.load();
  ASSERT_TRUE(r) << r.error;
  EXPECT_EQ(r.scene->lights.size(), dhr::kMaxSceneLights);
  EXPECT_EQ(r.scene->stats.lights_dropped, 4u);
  EXPECT_EQ(r.scene->lights.back().type, Type::kDisk);
  EXPECT_TRUE(has_warning(*r.scene, "keeping the first 256"));
}

}  // namespace
