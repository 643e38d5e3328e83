// dhr-xrclient --node-script's format (link/node_script.hpp): what a good script gives, and that every bad line is
// refused with its line number and why (the executable exits 2 before the run). The scene:
// tests/common/test_movable_scene.hpp (node 1 "Occluder" is movable, node 0 the static floor). And what the link
// layer does with the transforms (VisibilityClient::send_node_transform).
#include "client_harness.hpp"
#include "link/node_script.hpp"
#include "test_movable_scene.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace dhr::client {
namespace {

const Scene& movable_scene() {
  static const Scene* scene = [] {
    const std::string text = dhr::test::movable_occluder_gltf();
    SceneLoadResult loaded = load_scene_from_memory(text.data(), text.size(), ".", "movable.gltf");
    if (!loaded) throw std::runtime_error(loaded.error);
    return new Scene(std::move(*loaded.scene));
  }();
  return *scene;
}

std::string error_of(const std::string& text) {
  std::string error;
  EXPECT_FALSE(parse_node_script(text, movable_scene(), &error).has_value()) << text;
  return error;
}

TEST(NodeScript, ParsesNamesIndicesAndKeepsRestValuesNotGiven) {
  std::string error;
  const auto steps = parse_node_script(
      "# comment\n\n{\"t\": 0.5, \"node\": \"Occluder\", \"translation\": [1, 2, 3]}\n"
      "{\"t\": 1.25, \"node\": 1, \"rotation\": [0, 0, 0, 2e-4], \"scale\": [2, 2, 2]}\n",
      movable_scene(), &error);
  EXPECT_FALSE(steps.has_value());  // a rotation far from unit is refused...
  EXPECT_EQ(error, "line 4: not a usable transform: the rotation must be a unit quaternion [x, y, z, w] and every "
                   "scale > 0");
  const auto good = parse_node_script(
      "# comment\n\n{\"t\": 0.5, \"node\": \"Occluder\", \"translation\": [1, 2, 3]}\n"
      "{\"t\": 1.25, \"node\": 1, \"rotation\": [0, 0.6, 0, 0.8], \"scale\": [2, 2, 2]}\n",
      movable_scene(), &error);
  ASSERT_TRUE(good.has_value()) << error;
  ASSERT_EQ(good->size(), 2u);
  const NodeScriptStep& a = (*good)[0];
  EXPECT_EQ(a.line, 3u);
  EXPECT_EQ(a.node, dhr::test::kOccluderNode);
  EXPECT_EQ(a.scene_time_ns, 500'000'000);
  EXPECT_EQ(a.trs.translation, glm::dvec3(1.0, 2.0, 3.0));
  EXPECT_EQ(a.trs.rotation, glm::dquat(1.0, 0.0, 0.0, 0.0));  // rest
  EXPECT_EQ(a.trs.scale, glm::dvec3(1.0));                    // rest
  const NodeScriptStep& b = (*good)[1];
  EXPECT_EQ(b.line, 4u);
  EXPECT_EQ(b.scene_time_ns, 1'250'000'000);
  EXPECT_EQ(b.trs.translation, glm::dvec3(-1.5, 1.0, 0.0));  // rest
  EXPECT_NEAR(b.trs.rotation.y, 0.6, 1e-12);
  EXPECT_EQ(b.trs.scale, glm::dvec3(2.0));
}

TEST(NodeScript, EveryBadLineIsNamed) {
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 1}\n{\"t\": 1, \"node\": 1\n"), "line 2: not a JSON object");
  EXPECT_EQ(error_of("[1, 2]"), "line 1: expected a JSON object");
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": \"Nobody\"}"),
            "line 1: no node named \"Nobody\" that the scene lets move (animated, extras.dhr_movable, or below one)");
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 0}"),
            "line 1: node 0 is not a node the scene lets move (animated, extras.dhr_movable, or below one)");
  EXPECT_EQ(error_of("{\"t\": 0}"), "line 1: \"node\" is missing");
  EXPECT_EQ(error_of("{\"node\": 1}"), "line 1: \"t\" must be a scene time in seconds, 0 to 1e9");
  EXPECT_EQ(error_of("{\"t\": -1, \"node\": 1}"), "line 1: \"t\" must be a scene time in seconds, 0 to 1e9");
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 1, \"scale\": [1, 0, 1]}").rfind("line 1: not a usable transform", 0), 0u);
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 1, \"translation\": [1, 2]}"),
            "line 1: \"translation\" must be an array of 3 numbers");
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 1, \"translation\": [1, 2, \"x\"]}"),
            "line 1: \"translation\" must hold finite numbers");
  EXPECT_EQ(error_of("{\"t\": 0, \"node\": 1, \"colour\": 1}"),
            "line 1: unknown key \"colour\" (t, node, translation, rotation, scale)");
  EXPECT_EQ(error_of("{\"t\": 1, \"node\": 1}\n{\"t\": 0.5, \"node\": 1}"),
            "line 2: \"t\" is before the previous line's: lines must be in time order");
  EXPECT_EQ(error_of("{\"t\": 1, \"node\": 1}\n{\"t\": 1, \"node\": 1}"),
            "line 2: \"t\" must be after the same node's previous line (node 1)");
}

TEST(NodeScript, AFileNamesItselfAndTheLine) {
  const std::string path = ::testing::TempDir() + "dhr_node_script_test.jsonl";
  {
    std::ofstream out(path);
    out << "{\"t\": 0, \"node\": 1}\n{\"t\": 1, \"node\": 7}\n";
  }
  std::string error;
  EXPECT_FALSE(load_node_script(path, movable_scene(), &error).has_value());
  EXPECT_EQ(error.rfind(path + ":2: node 7 is not a node", 0), 0u) << error;
  std::remove(path.c_str());
  EXPECT_FALSE(load_node_script(path, movable_scene(), &error).has_value());
  EXPECT_EQ(error, path + ": cannot read the file");
}

// send_node_transform: sent only within a session, as the server will decode it; the newest two per node go again
// to a new session's server (its copy went with the old session).
TEST(NodeTransformLink, TheNewestTwoPerNodeAreResentToANewSession) {
  test::Harness h;
  EXPECT_FALSE(h.client.send_node_transform(1, 0, dhr::test::occluder_at(0.0)).has_value());  // no session yet
  h.connect();
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(h.client.send_node_transform(1, (i + 1) * 100 * test::kMs, dhr::test::occluder_at(i)).has_value());
  ASSERT_TRUE(h.client.send_node_transform(4, 50 * test::kMs, dhr::test::occluder_at(7.0)).has_value());
  Trs bad = dhr::test::occluder_at(0.0);
  bad.scale.x = 0.0;
  EXPECT_FALSE(h.client.send_node_transform(1, 400 * test::kMs, bad).has_value());
  h.run_for(test::kMs);
  EXPECT_EQ(h.received<NodeTransform>().size(), 4u);
  h.run_for(5'100 * test::kMs);  // the scripted server stays silent: the session times out
  ASSERT_FALSE(h.client.connected());
  h.server_send(h.welcome_for(h.received<Hello>().back().client_nonce));
  h.run_for(test::kMs);
  ASSERT_TRUE(h.client.connected());
  h.run_for(test::kMs);  // the resent transforms reach the server
  const std::vector<NodeTransform> all = h.received<NodeTransform>();
  ASSERT_EQ(all.size(), 7u);
  const std::vector<NodeTransform> resent(all.begin() + 4, all.end());  // by node, the older first
  EXPECT_EQ(resent[0].node, 1u);
  EXPECT_EQ(resent[0].scene_time_ns, 200 * test::kMs);
  EXPECT_EQ(resent[1].scene_time_ns, 300 * test::kMs);
  EXPECT_EQ(resent[2].node, 4u);
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.node_transforms_sent, 4u);
  EXPECT_EQ(s.node_transforms_not_connected, 1u);
  EXPECT_EQ(s.node_transforms_refused, 1u);
  EXPECT_EQ(s.node_transforms_resent, 3u);
}

}  // namespace
}  // namespace dhr::client
