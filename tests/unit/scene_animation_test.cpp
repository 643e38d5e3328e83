// glTF animations in the scene loader: sampling (LINEAR, STEP, CUBICSPLINE, slerp, looping), the hierarchy, lights
// and meshes on animated nodes, static scenes, refusals of bad animation data, and the moving living room when the
// shared data is present. The glTF files are written by the tests (base64 data URIs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "test_gltf.hpp"
#include "scene/scene_hash.hpp"

namespace {

using nlohmann::json;

// A glTF document with one embedded buffer and one animation ("anim"); tests add nodes and channels.
class AnimGltf : public dhr::test::TestGltf {
 public:
  // A one-triangle mesh (0,0,0) (1,0,0) (0,1,0).
  int triangle_mesh() {
    const int pos = floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    doc["meshes"].push_back({{"primitives", json::array({{{"attributes", {{"POSITION", pos}}}}})}});
    return static_cast<int>(doc["meshes"].size()) - 1;
  }
  // Adds a sampler (times, values with `components` floats each) and a channel on `node`/`path` to "anim".
  void channel(int node, const char* path, const std::vector<float>& times, const std::vector<float>& values,
               const char* interpolation = "LINEAR") {
    const int input = floats(times, "SCALAR", 1);
    const std::size_t components = std::string(path) == "rotation" ? 4 : 3;
    const int output = floats(values, components == 4 ? "VEC4" : "VEC3", components);
    channel_with(node, path, input, output, interpolation);
  }
  void channel_with(int node, const char* path, int input, int output, const char* interpolation = "LINEAR") {
    json& anim = animation();
    anim["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
    anim["channels"].push_back(
        {{"sampler", anim["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  }
  json& animation() {
    if (!doc.contains("animations")) doc["animations"] = json::array({{{"name", "anim"}}});
    return doc["animations"][0];
  }
};

dhr::SceneLoadResult load(const std::string& text, const dhr::SceneLoadOptions& options = {}) {
  return dhr::load_scene_from_memory(text.data(), text.size(), ".", "anim.gltf", options);
}

void expect_error(const dhr::SceneLoadResult& r, std::vector<std::string> phrases) {
  ASSERT_FALSE(r.ok()) << "loaded, but expected an error containing: " << phrases[0];
  for (const std::string& p : phrases) EXPECT_NE(r.error.find(p), std::string::npos) << r.error << "\nwanted: " << p;
}

bool has_warning(const dhr::Scene& scene, const std::string& phrase) {
  for (const auto& w : scene.warnings) {
    if (w.find(phrase) != std::string::npos) return true;
  }
  return false;
}

glm::dvec3 origin_at(const dhr::Scene& scene, std::uint32_t node, double t) {
  return glm::dvec3(dhr::node_world_at(scene, node, t)[3]);
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

const float kS45 = static_cast<float>(std::sqrt(0.5));  // sin 45 = cos 45

TEST(SceneAnimation, LinearTranslationAtKeysMidwayAndLooping) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}, {"translation", {5, 5, 5}}});
  g.channel(0, "translation", {0, 1, 2}, {0, 0, 0, 2, 0, 0, 2, 4, 0});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  const dhr::Scene& s = *r.scene;
  ASSERT_FALSE(s.animation.empty());
  ASSERT_EQ(s.animation.clips.size(), 1u);
  EXPECT_EQ(s.animation.clips[0].name, "anim");
  EXPECT_EQ(s.animation.clips[0].duration, 2.0);
  ASSERT_EQ(s.animation.tracks.size(), 1u);
  EXPECT_EQ(s.animation.moving_nodes, std::vector<std::uint32_t>{0});
  EXPECT_FALSE(has_warning(s, "animation"));
  EXPECT_EQ(origin_at(s, 0, 0.0), glm::dvec3(0, 0, 0));
  EXPECT_EQ(origin_at(s, 0, 1.0), glm::dvec3(2, 0, 0));
  EXPECT_EQ(origin_at(s, 0, 0.5), glm::dvec3(1, 0, 0));
  EXPECT_EQ(origin_at(s, 0, 1.5), glm::dvec3(2, 2, 0));
  // Looping: t = duration + x is t = x; negative and non-finite times count as 0.
  EXPECT_EQ(origin_at(s, 0, 2.5), origin_at(s, 0, 0.5));
  EXPECT_EQ(origin_at(s, 0, 2.0), origin_at(s, 0, 0.0));
  EXPECT_EQ(origin_at(s, 0, 41.5), origin_at(s, 0, 1.5));
  EXPECT_EQ(origin_at(s, 0, -3.0), glm::dvec3(0, 0, 0));
  EXPECT_EQ(origin_at(s, 0, std::numeric_limits<double>::quiet_NaN()), glm::dvec3(0, 0, 0));
  EXPECT_EQ(origin_at(s, 0, std::numeric_limits<double>::infinity()), glm::dvec3(0, 0, 0));
  EXPECT_EQ(dhr::animation_local_time(7.5, 0.0), 0.0);
}

TEST(SceneAnimation, StepHoldsTheKeyValue) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.channel(0, "translation", {0, 1, 2}, {1, 0, 0, 3, 0, 0, 7, 0, 0}, "STEP");
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  EXPECT_EQ(origin_at(*r.scene, 0, 0.0).x, 1.0);
  EXPECT_EQ(origin_at(*r.scene, 0, 0.99).x, 1.0);
  EXPECT_EQ(origin_at(*r.scene, 0, 1.0).x, 3.0);
  EXPECT_EQ(origin_at(*r.scene, 0, 1.7).x, 3.0);
}

TEST(SceneAnimation, CubicSplineIsTheHermiteOfTheSpec) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  // Keys at 0 and 2 (dt = 2): x from 0 (out-tangent 3) to 1 (in-tangent -1); y constant 5 with zero tangents.
  // u = 0.5: 0.5 * 0 + 0.125 * dt * 3 + 0.5 * 1 - 0.125 * dt * (-1) = 0.75 + 0.5 + 0.25 = 1.5.
  g.channel(0, "translation", {0, 2},
            {/*key 0*/ 9, 9, 9, 0, 5, 0, 3, 0, 0, /*key 1*/ -1, 0, 0, 1, 5, 0, 9, 9, 9}, "CUBICSPLINE");
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  expect_near(origin_at(*r.scene, 0, 1.0), {1.5, 5.0, 0.0});
  expect_near(origin_at(*r.scene, 0, 0.0), {0.0, 5.0, 0.0});
  EXPECT_EQ(r.scene->animation.tracks[0].values.size(), 18u);
}

// Where the node's +X axis points at t (rotation about Y only).
glm::dvec3 x_axis_at(const dhr::Scene& s, std::uint32_t node, double t) {
  return glm::dvec3(dhr::node_world_at(s, node, t) * glm::dvec4(1, 0, 0, 0));
}

TEST(SceneAnimation, RotationSlerpsOnTheShortestPath) {
  for (const float sign : {1.0f, -1.0f}) {  // -q1 is the same rotation: the negative dot takes the short way
    AnimGltf g;
    g.node({{"mesh", g.triangle_mesh()}});
    g.channel(0, "rotation", {0, 1, 2}, {0, 0, 0, 1, 0, sign * kS45, 0, sign * kS45, 0, 0, 0, 1});
    auto r = load(g.text());
    ASSERT_TRUE(r) << r.error;
    // Ry(a) maps +X to (cos a, 0, -sin a).
    for (const double deg : {45.0, 22.5, 90.0, 67.5}) {
      const double a = glm::radians(deg);
      expect_near(x_axis_at(*r.scene, 0, deg / 90.0), {std::cos(a), 0.0, -std::sin(a)}, 1e-7);
    }
  }
}

TEST(SceneAnimation, NormalizedShortRotationsAreRead) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  const std::vector<std::int16_t> q = {0, 0, 0, 32767, 0, 23170, 0, 23170};  // identity, 90 degrees about Y
  const int input = g.floats({0, 1}, "SCALAR", 1);
  const int output = g.accessor(q.data(), q.size() * 2, 5122, 2, "VEC4", true);
  g.channel_with(0, "rotation", input, output);
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  expect_near(x_axis_at(*r.scene, 0, 0.5), {std::sqrt(0.5), 0.0, -std::sqrt(0.5)}, 1e-6);
}

TEST(SceneAnimation, ChildOfAnAnimatedParentMoves) {
  AnimGltf g;
  g.node({{"children", {1}}, {"translation", {0, 0, 7}}});
  g.node({{"mesh", g.triangle_mesh()}, {"translation", {0, 1, 0}}});
  g.node({{"mesh", g.triangle_mesh()}, {"translation", {4, 0, 0}}});  // static
  g.channel(0, "translation", {0, 2}, {0, 0, 0, 4, 0, 0});
  auto r = load(g.text({0, 2}));
  ASSERT_TRUE(r) << r.error;
  const dhr::Scene& s = *r.scene;
  EXPECT_EQ(s.animation.moving_nodes, (std::vector<std::uint32_t>{0, 1}));
  ASSERT_NE(s.animation.find(1), nullptr);
  EXPECT_EQ(s.animation.find(1)->track_count, 0u);
  EXPECT_EQ(s.animation.find(1)->parent, 0u);
  EXPECT_EQ(s.animation.find(2), nullptr);
  expect_near(origin_at(s, 1, 1.0), {2, 1, 0});
  expect_near(origin_at(s, 2, 1.0), {4, 0, 0});  // static: its rest transform
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(dhr::mesh_motion_at(s, s.meshes[1], 1.0), glm::dmat4(1.0));
}

TEST(SceneAnimation, MeshMotionMapsRestVerticesToTheirPositionAtT) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}, {"translation", {5, 0, 0}}});
  g.channel(0, "translation", {0, 1}, {0, 0, 0, 0, 2, 0});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  const dhr::SceneMesh& m = r.scene->meshes[0];
  const glm::dvec3 rest(m.positions[1]);  // local (1,0,0) at rest: (6,0,0)
  EXPECT_EQ(rest, glm::dvec3(6, 0, 0));
  const glm::dvec4 moved = dhr::mesh_motion_at(*r.scene, m, 0.5) * glm::dvec4(rest, 1.0);
  expect_near(glm::dvec3(moved), {1, 1, 0});
}

TEST(SceneAnimation, LightOnAnAnimatedNodeMoves) {
  AnimGltf g;
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] =
      json::array({{{"type", "spot"}, {"spot", json::object()}, {"intensity", 10}}, {{"type", "point"}}});
  g.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.node({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});  // static
  g.channel(0, "translation", {0, 1, 2}, {0, 0, 0, 0, 4, 0, 0, 0, 0});
  g.channel(0, "rotation", {0, 1, 2}, {0, 0, 0, 1, 0, kS45, 0, kS45, 0, 0, 0, 1});
  auto r = load(g.text({0, 1}));
  ASSERT_TRUE(r) << r.error;
  const dhr::Scene& s = *r.scene;
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].node, 0u);
  EXPECT_EQ(s.lights[1].node, 1u);
  expect_near(glm::dvec3(s.lights[0].position), {1, 2, 3}, 0.0);  // the rest pose
  const dhr::SceneLight at1 = dhr::light_at(s, s.lights[0], 1.0);
  expect_near(glm::dvec3(at1.position), {0, 4, 0}, 1e-6);
  expect_near(glm::dvec3(at1.direction), {-1, 0, 0}, 1e-6);  // -Z rotated 90 degrees about Y
  const dhr::SceneLight at0 = dhr::light_at(s, s.lights[0], 0.0);
  expect_near(glm::dvec3(at0.position), {0, 0, 0}, 1e-6);
  expect_near(glm::dvec3(at0.direction), {0, 0, -1}, 1e-6);
  const dhr::SceneLight still = dhr::light_at(s, s.lights[1], 1.0);
  EXPECT_EQ(still.position, s.lights[1].position);
  // Lights from specs have no node and never move.
  dhr::SceneLight spec;
  EXPECT_EQ(spec.node, dhr::kNoSceneNode);
  EXPECT_EQ(dhr::light_at(s, spec, 1.0).position, spec.position);
}

TEST(SceneAnimation, AnimationsLoopWithTheirOwnDuration) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.node({{"mesh", g.triangle_mesh()}});
  g.channel(0, "translation", {0, 2}, {0, 0, 0, 2, 0, 0});
  g.doc["animations"].push_back({{"name", "b"}});
  const int in = g.floats({0, 4}, "SCALAR", 1);
  const int out = g.floats({0, 0, 0, 4, 0, 0}, "VEC3", 3);
  g.doc["animations"][1]["samplers"] = json::array({{{"input", in}, {"output", out}}});  // LINEAR by default
  g.doc["animations"][1]["channels"] =
      json::array({{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}});
  auto r = load(g.text({0, 1}));
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->animation.clips.size(), 2u);
  EXPECT_EQ(r.scene->animation.clips[1].duration, 4.0);
  expect_near(origin_at(*r.scene, 0, 3.0), {1, 0, 0});
  expect_near(origin_at(*r.scene, 1, 3.0), {3, 0, 0});
}

TEST(SceneAnimation, SamplingIsDeterministic) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}, {"scale", {2, 2, 2}}});
  g.channel(0, "rotation", {0, 0.7f, 1.9f}, {0, 0, 0, 1, 0.3f, 0.5f, 0.1f, 0.8f, -0.2f, 0.1f, 0.9f, 0.3f});
  g.channel(0, "translation", {0, 1.3f}, {0, 1, 0, 3, 0, 0, 0, 2, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0}, "CUBICSPLINE");
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  for (const double t : {0.0, 0.1234567, 1.05, 1.7, 123.456}) {
    const glm::dmat4 a = dhr::node_world_at(*r.scene, 0, t);
    const glm::dmat4 b = dhr::node_world_at(*r.scene, 0, t);
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << t;
  }
}

TEST(SceneAnimation, StaticScenesAreUnchanged) {
  AnimGltf g;
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}}});
  g.node({{"mesh", g.triangle_mesh()}, {"translation", {1, 0, 0}}, {"children", {1}}});
  g.node({{"translation", {0, 2, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  dhr::Scene s = *r.scene;
  EXPECT_TRUE(s.animation.empty());
  EXPECT_TRUE(s.animation.moving_nodes.empty());
  EXPECT_TRUE(s.animation.clips.empty());
  EXPECT_EQ(dhr::mesh_motion_at(s, s.meshes[0], 1.0), glm::dmat4(1.0));
  EXPECT_EQ(dhr::node_world_at(s, 0, 1.0), s.meshes[0].T_world_local);
  EXPECT_EQ(dhr::light_at(s, s.lights[0], 1.0).position, s.lights[0].position);
  EXPECT_EQ(s.lights[0].node, 1u);
  // The hash of a static scene covers neither the light nodes nor the (empty) animation: it is the hash of the
  // same scene without them, as before animations were loaded.
  const std::uint64_t h = dhr::scene_content_hash(s);
  s.lights[0].node = dhr::kNoSceneNode;
  s.animation = dhr::SceneAnimation{};
  EXPECT_EQ(dhr::scene_content_hash(s), h);
}

TEST(SceneAnimation, AnimationDataChangesTheHash) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.channel(0, "translation", {0, 1}, {0, 0, 0, 1, 0, 0});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  dhr::Scene s = *r.scene;
  const std::uint64_t h = dhr::scene_content_hash(s);
  s.animation.tracks[0].values[3] = 2.0f;
  EXPECT_NE(dhr::scene_content_hash(s), h);
  s.animation = dhr::SceneAnimation{};
  EXPECT_NE(dhr::scene_content_hash(s), h);
}

TEST(SceneAnimation, IgnoredChannelsWarn) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.node({{"mesh", g.triangle_mesh()}});  // not in the scene
  g.channel(0, "weights", {0, 1}, {0, 0, 0, 1, 0, 0});
  g.channel(1, "translation", {0, 1}, {0, 0, 0, 1, 0, 0});
  auto r = load(g.text({0}));
  ASSERT_TRUE(r) << r.error;
  EXPECT_TRUE(has_warning(*r.scene, "animation 0 ('anim') channel 0: morph target weights"));
  EXPECT_TRUE(has_warning(*r.scene, "animation 0 ('anim') channel 1: node 1 is not in the loaded scene"));
  EXPECT_TRUE(r.scene->animation.empty());
}

// One node with a mesh and one translation channel whose sampler the caller may break.
AnimGltf one_channel(const std::vector<float>& times, const std::vector<float>& values,
                     const char* interpolation = "LINEAR") {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.channel(0, "translation", times, values, interpolation);
  return g;
}

TEST(SceneAnimation, RefusesBadKeyTimes) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expect_error(load(one_channel({0, 1, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0}).text()),
               {"animation 0 ('anim') channel 0", "not strictly increasing"});
  expect_error(load(one_channel({0, 2, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0}).text()), {"not strictly increasing"});
  expect_error(load(one_channel({0, nan}, {0, 0, 0, 1, 0, 0}).text()), {"channel 0", "key time 1 is not finite"});
  expect_error(load(one_channel({-1, 1}, {0, 0, 0, 1, 0, 0}).text()), {"channel 0", "key time 0 is negative"});
}

TEST(SceneAnimation, RefusesBadValues) {
  const float inf = std::numeric_limits<float>::infinity();
  expect_error(load(one_channel({0, 1}, {0, 0, 0, inf, 0, 0}).text()), {"channel 0", "value 1 is NaN or infinite"});
  expect_error(load(one_channel({0, 1, 2}, {0, 0, 0, 1, 0, 0}).text()), {"channel 0", "2 values for 3 keys"});
  expect_error(load(one_channel({0, 1}, {0, 0, 0, 1, 0, 0}, "CUBICSPLINE").text()), {"2 values for 2 keys", "6"});
}

TEST(SceneAnimation, RefusesBadTargetsAndReferences) {
  AnimGltf g = one_channel({0, 1}, {0, 0, 0, 1, 0, 0});
  g.animation()["channels"][0]["target"]["node"] = 9;
  expect_error(load(g.text()), {"animations[0] ('anim').channels[0].target.node", "refers to node 9"});
  g = one_channel({0, 1}, {0, 0, 0, 1, 0, 0});
  g.animation()["channels"][0]["target"].erase("node");
  expect_error(load(g.text()), {"animations[0] ('anim').channels[0].target", "has no node"});
  g = one_channel({0, 1}, {0, 0, 0, 1, 0, 0});
  g.animation()["channels"][0]["target"]["path"] = "color";
  expect_error(load(g.text()), {"channels[0].target.path", "unknown path \"color\""});
  g = one_channel({0, 1}, {0, 0, 0, 1, 0, 0});
  g.animation()["channels"][0]["sampler"] = 3;
  expect_error(load(g.text()), {"channels[0].sampler", "refers to sampler 3"});
  g = one_channel({0, 1}, {0, 0, 0, 1, 0, 0});
  g.animation()["samplers"][0]["interpolation"] = "BEZIER";
  expect_error(load(g.text()),
               {"animations[0] ('anim').samplers[0].interpolation", "unknown interpolation \"BEZIER\""});
}

TEST(SceneAnimation, RefusesWrongAccessorTypes) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}});
  g.channel(0, "translation", {0, 1}, {0, 0, 0, 0, 1, 0, 0, 0});  // VEC4 values, read as VEC3 below
  g.doc["accessors"][g.animation()["samplers"][0]["output"].get<int>()]["type"] = "VEC4";
  g.doc["accessors"][g.animation()["samplers"][0]["output"].get<int>()]["count"] = 2;
  expect_error(load(g.text()), {"channel 0", "translations and scales must be a VEC3 float accessor"});

  AnimGltf h;
  h.node({{"mesh", h.triangle_mesh()}});
  const std::vector<std::int16_t> q = {0, 0, 0, 32767, 0, 23170, 0, 23170};
  const int input = h.floats({0, 1}, "SCALAR", 1);
  h.channel_with(0, "rotation", input, h.accessor(q.data(), q.size() * 2, 5122, 2, "VEC4", false));
  expect_error(load(h.text()), {"channel 0", "rotations must be a VEC4 accessor of floats or normalized integers"});

  AnimGltf k;
  k.node({{"mesh", k.triangle_mesh()}});
  const int times = k.floats({0, 1, 2, 0, 1, 2}, "VEC3", 3);
  k.channel_with(0, "translation", times, k.floats({0, 0, 0, 1, 0, 0}, "VEC3", 3));
  expect_error(load(k.text()), {"channel 0", "key times must be a SCALAR float accessor"});
}

TEST(SceneAnimation, RefusesAnAnimatedMatrixNode) {
  AnimGltf g;
  g.node({{"mesh", g.triangle_mesh()}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
  g.channel(0, "translation", {0, 1}, {0, 0, 0, 1, 0, 0});
  expect_error(load(g.text()), {"animation 0 ('anim') channel 0", "node 0 is given by a matrix"});
}

TEST(SceneAnimation, RefusesMoreKeysThanTheLimit) {
  dhr::SceneLoadOptions options;
  options.max_animation_keys = 2;
  expect_error(load(one_channel({0, 1, 2}, {0, 0, 0, 1, 0, 0, 2, 0, 0}).text(), options),
               {"3 keys", "max_animation_keys"});
  options.max_animation_keys = 3;
  EXPECT_TRUE(load(one_channel({0, 1, 2}, {0, 0, 0, 1, 0, 0, 2, 0, 0}).text(), options).ok());
}

TEST(SceneAnimation, LivingRoomMoving) {
  const std::filesystem::path file = std::filesystem::path(DHR_SHARED_DATA_DIR) / "scenes/living_room_moving.glb";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "test data not available: " << file.string();
  dhr::SceneLoadOptions options;
  options.decode_images = false;
  auto r = dhr::load_scene(file.string(), options);
  ASSERT_TRUE(r) << r.error;
  const dhr::Scene& s = *r.scene;
  ASSERT_EQ(s.animation.clips.size(), 1u);
  EXPECT_EQ(s.animation.clips[0].duration, 6.0);
  ASSERT_EQ(s.animation.tracks.size(), 3u);
  std::vector<std::uint32_t> animated;
  for (const dhr::AnimatedNode& n : s.animation.nodes) {
    if (n.track_count > 0) animated.push_back(n.node);
  }
  EXPECT_EQ(animated, (std::vector<std::uint32_t>{27, 30, 32}));
  // The toy car's (24-26) and the duck's (28, 29) nodes move with their animated parents.
  EXPECT_EQ(s.animation.moving_nodes, (std::vector<std::uint32_t>{24, 25, 26, 27, 28, 29, 30, 32}));
  const dhr::SceneLight* light = nullptr;
  for (const dhr::SceneLight& l : s.lights) {
    if (l.name == "Ceiling_Point_A") light = &l;
  }
  ASSERT_NE(light, nullptr);
  const glm::dvec3 p0(dhr::light_at(s, *light, 0.0).position);
  const glm::dvec3 p15(dhr::light_at(s, *light, 1.5).position);
  const glm::dvec3 p6(dhr::light_at(s, *light, 6.0).position);
  EXPECT_GT(glm::length(p15 - p0), 1e-3);
  expect_near(p6, p0, 1e-9);
  std::size_t car_meshes = 0;
  for (const dhr::SceneMesh& m : s.meshes) {
    const bool car = m.node >= 24 && m.node <= 26;
    const bool moves = dhr::mesh_motion_at(s, m, 1.5) != glm::dmat4(1.0);
    if (car) {
      ++car_meshes;
      EXPECT_TRUE(moves) << m.name;
    } else if (m.node != 29) {
      EXPECT_FALSE(moves) << m.name;
    }
  }
  EXPECT_GT(car_meshes, 0u);
}

}  // namespace
