// A light's extent outside the loader: validate_light's rules, the --lights spec syntax for rect/disk lights and
// the radius=/angle_deg= fields (round trip through format_light_spec), the description --check prints, and the
// scene content hash.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <string>

#include "scene/scene.hpp"
#include "scene/scene_hash.hpp"

namespace {

using dhr::SceneLight;
using Type = SceneLight::Type;

SceneLight rect_light() {
  SceneLight l;
  l.type = Type::kRect;
  l.name = "panel";
  l.position = {0, 2.5f, 0};
  l.direction = {0, -1, 0};
  l.tangent = {1, 0, 0};
  l.bitangent = {0, 0, -1};
  l.intensity = 50.0f;
  l.width = 0.8f;
  l.height = 0.4f;
  return l;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(SceneLightExtent, ValidateCoversTheExtent) {
  EXPECT_FALSE(dhr::validate_light(rect_light()).has_value());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    void (*change)(SceneLight&, float, float);
    const char* phrase;
  };
  const Case cases[] = {
      {[](SceneLight& l, float n, float) { l.width = n; }, "non-finite extent"},
      {[](SceneLight& l, float, float i) { l.height = i; }, "non-finite extent"},
      {[](SceneLight& l, float n, float) { l.tangent.x = n; }, "non-finite extent"},
      {[](SceneLight& l, float, float) { l.width = -1.0f; }, "negative extent"},
      {[](SceneLight& l, float, float) { l.width = 0.0f; }, "positive width and height"},
      {[](SceneLight& l, float, float) { l.width = 101.0f; }, "larger than 100 m"},
      {[](SceneLight& l, float, float) { l.radius = 0.1f; }, "only point and spot lights take a radius"},
      {[](SceneLight& l, float, float) { l.angle = 0.01f; }, "only directional lights take an angle"},
      {[](SceneLight& l, float, float) { l.tangent = {0, 1, 0}; }, "orthonormal frame"},
      {[](SceneLight& l, float, float) { l.bitangent = {0, 0, -2}; }, "orthonormal frame"},
      {[](SceneLight& l, float, float) { l.type = Type::kDisk; }, "width == height"},
      {[](SceneLight& l, float, float) { l.type = Type::kPoint; }, "only rect and disk lights take a width"},
  };
  for (const Case& c : cases) {
    SceneLight l = rect_light();
    c.change(l, nan, inf);
    const auto problem = dhr::validate_light(l);
    ASSERT_TRUE(problem.has_value()) << c.phrase;
    EXPECT_NE(problem->find(c.phrase), std::string::npos) << *problem;
  }
  SceneLight sphere;
  sphere.radius = 0.06f;
  EXPECT_FALSE(dhr::validate_light(sphere).has_value());
  sphere.radius = -0.06f;
  EXPECT_TRUE(dhr::validate_light(sphere).has_value());
  sphere.radius = nan;
  EXPECT_TRUE(dhr::validate_light(sphere).has_value());
  SceneLight sun;
  sun.type = Type::kDirectional;
  sun.angle = 0.0093f;
  EXPECT_FALSE(dhr::validate_light(sun).has_value());
  sun.angle = 0.6f;
  EXPECT_NE(dhr::validate_light(sun).value_or("").find("above 0.5 rad"), std::string::npos);
}

TEST(SceneLightExtent, RectAndDiskSpecsRoundTrip) {
  const SceneLight rect = rect_light();
  const std::string spec = dhr::format_light_spec(rect);
  EXPECT_EQ(spec, "rect:0,2.5,0:0,-1,0:1,0,0:1,1,1:50:0.800000012,0.400000006");
  std::string error;
  auto parsed = dhr::parse_light_spec(spec, &error);
  ASSERT_TRUE(parsed) << error;
  EXPECT_EQ(parsed->type, Type::kRect);
  EXPECT_EQ(parsed->position, rect.position);
  EXPECT_EQ(parsed->direction, rect.direction);
  EXPECT_EQ(parsed->tangent, rect.tangent);
  expect_near(parsed->bitangent, rect.bitangent);
  EXPECT_EQ(parsed->width, rect.width);
  EXPECT_EQ(parsed->height, rect.height);
  EXPECT_EQ(parsed->intensity, rect.intensity);
  EXPECT_EQ(dhr::format_light_spec(*parsed), spec);
  // A tangent that is not orthogonal to the direction is made so; the bitangent completes the frame.
  auto disk = dhr::parse_light_spec("disk:1,2,3:0,0,-2:1,0,1:1,0.9,0.8:90:0.6,0.6:5", &error);
  ASSERT_TRUE(disk) << error;
  EXPECT_EQ(disk->type, Type::kDisk);
  expect_near(disk->direction, {0, 0, -1});
  expect_near(disk->tangent, {1, 0, 0});
  expect_near(disk->bitangent, {0, 1, 0});
  EXPECT_FLOAT_EQ(disk->range, 5.0f);
  auto again = dhr::parse_light_spec(dhr::format_light_spec(*disk), &error);
  ASSERT_TRUE(again) << error;
  EXPECT_EQ(dhr::format_light_spec(*again), dhr::format_light_spec(*disk));
}

TEST(SceneLightExtent, RadiusAndAngleSpecFieldsRoundTrip) {
  std::string error;
  auto sphere = dhr::parse_light_spec("point:1,2,3:1,1,1:8:6:radius=0.06", &error);
  ASSERT_TRUE(sphere) << error;
  EXPECT_FLOAT_EQ(sphere->radius, 0.06f);
  EXPECT_FLOAT_EQ(sphere->range, 6.0f);
  auto no_range = dhr::parse_light_spec("point:1,2,3:1,1,1:8:radius=0.06", &error);
  ASSERT_TRUE(no_range) << error;
  EXPECT_FLOAT_EQ(no_range->range, 0.0f);
  auto spot = dhr::parse_light_spec("spot:0,3,0:0,-1,0:1,1,1:100:20,30:radius=0.1", &error);
  ASSERT_TRUE(spot) << error;
  EXPECT_FLOAT_EQ(spot->radius, 0.1f);
  auto sun = dhr::parse_light_spec("dir:0,-1,0:1,1,1:6:angle_deg=0.53", &error);
  ASSERT_TRUE(sun) << error;
  EXPECT_NEAR(sun->angle, 0.53 * M_PI / 180.0, 1e-7);
  for (const SceneLight* l : {&*sphere, &*no_range, &*spot, &*sun}) {
    auto again = dhr::parse_light_spec(dhr::format_light_spec(*l), &error);
    ASSERT_TRUE(again) << error;
    EXPECT_NEAR(again->radius, l->radius, 1e-7f);
    EXPECT_NEAR(again->angle, l->angle, 1e-7f);
    EXPECT_EQ(again->range, l->range);
    EXPECT_EQ(dhr::format_light_spec(*again), dhr::format_light_spec(*l));
  }
  // Punctual lights print as they always did.
  EXPECT_EQ(dhr::format_light_spec(*dhr::parse_light_spec("point:1,2,3:1,1,1:8", nullptr)), "point:1,2,3:1,1,1:8");
}

TEST(SceneLightExtent, MalformedExtentSpecsAreRejectedWithAReason) {
  const std::pair<const char*, const char*> cases[] = {
      {"point:0,0,0:1,1,1:1:radius=-1", "negative extent"},
      {"point:0,0,0:1,1,1:1:radius=200", "larger than 100 m"},
      {"point:0,0,0:1,1,1:1:radius=x", "radius: \"x\" is not a finite number"},
      {"point:0,0,0:1,1,1:1:angle_deg=1", "unknown or misplaced field \"angle_deg=1\""},
      {"dir:0,-1,0:1,1,1:1:radius=1", "unknown or misplaced field"},
      {"dir:0,-1,0:1,1,1:1:angle_deg=40", "above 0.5 rad"},
      {"point:0,0,0:radius=1:1,1,1:1", "named field \"radius=1\" must follow the others"},
      {"rect:0,0,0:0,-1,0:1,0,0:1,1,1:50", "expected rect:x,y,z:dx,dy,dz:tx,ty,tz:r,g,b:nits:width,height"},
      {"rect:0,0,0:0,-1,0:0,1,0:1,1,1:50:1,1", "tangent must not be parallel"},
      {"rect:0,0,0:0,0,0:1,0,0:1,1,1:50:1,1", "direction must not be zero"},
      {"rect:0,0,0:0,-1,0:1,0,0:1,1,1:50:0,1", "positive width and height"},
      {"rect:0,0,0:0,-1,0:1,0,0:1,1,1:50:1", "width,height: expected 2"},
      {"disk:0,0,0:0,-1,0:1,0,0:1,1,1:50:1,2", "width == height"},
      {"rect:0,0,0:0,-1,0:1,0,0:1,1,1:50:1,1:radius=1", "unknown or misplaced field"},
  };
  for (const auto& [spec, phrase] : cases) {
    std::string error;
    EXPECT_FALSE(dhr::parse_light_spec(spec, &error)) << spec;
    EXPECT_NE(error.find(phrase), std::string::npos) << spec << " -> " << error;
  }
}

TEST(SceneLightExtent, DescriptionsNameTypeAndExtent) {
  EXPECT_EQ(dhr::describe_light_extent(rect_light()), "rect 0.8 x 0.4 m");
  SceneLight l;
  EXPECT_EQ(dhr::describe_light_extent(l), "point");
  l.radius = 0.06f;
  EXPECT_EQ(dhr::describe_light_extent(l), "point, sphere r 0.06 m");
  l = SceneLight{};
  l.type = Type::kDirectional;
  l.angle = 0.0093f;
  EXPECT_EQ(dhr::describe_light_extent(l), "dir, sun disk 0.533 deg");
  l = rect_light();
  l.type = Type::kDisk;
  l.height = l.width;
  EXPECT_EQ(dhr::describe_light_extent(l), "disk 0.8 m");
}

TEST(SceneLightExtent, TheContentHashCoversTheExtent) {
  dhr::Scene scene;
  SceneLight point;
  point.position = {1, 2, 3};
  scene.lights = {point, rect_light()};
  const std::uint64_t base = dhr::scene_content_hash(scene);
  auto changed = [&](auto&& change) {
    dhr::Scene copy = scene;
    change(copy.lights);
    return dhr::scene_content_hash(copy);
  };
  EXPECT_NE(changed([](auto& l) { l[0].radius = 0.06f; }), base);
  dhr::Scene with_radius = scene;
  with_radius.lights[0].radius = 0.06f;
  const std::uint64_t h = dhr::scene_content_hash(with_radius);
  with_radius.lights[0].radius = 0.07f;
  EXPECT_NE(dhr::scene_content_hash(with_radius), h);  // a different radius, a different hash
  EXPECT_NE(changed([](auto& l) { l[1].width = 0.9f; }), base);
  EXPECT_NE(changed([](auto& l) { l[1].height = 0.3f; }), base);
  EXPECT_NE(changed([](auto& l) { l[1].tangent = {0, 0, 1}; }), base);
  EXPECT_NE(changed([](auto& l) { l[1].type = SceneLight::Type::kDisk; }), base);
  EXPECT_EQ(changed([](auto&) {}), base);
}

}  // namespace
