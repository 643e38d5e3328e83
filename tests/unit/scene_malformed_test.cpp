// Malformed input built in the test: one valid one-triangle glTF, broken in one way per test. Every
// case must give an error naming the file and the problem (never a crash), or load with a warning.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace {

using nlohmann::json;

// 3 float3 positions (0,0,0) (1,0,0) (0,1,0), then uint32 indices 0 1 2.
constexpr const char* kBuffer =
    "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAEAAAACAAAA";
// Same with x of vertex 1 = NaN.
constexpr const char* kNanBuffer =
    "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAADAfwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAEAAAACAAAA";

json valid() {
  return json::parse(std::string(R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
    "buffers": [{"byteLength": 48, "uri": ")") +
                     kBuffer + R"("}]})");
}

dhr::SceneLoadResult load_text(const std::string& text, const dhr::SceneLoadOptions& options = {}) {
  return dhr::load_scene_from_memory(text.data(), text.size(), ".", "broken.gltf", options);
}

dhr::SceneLoadResult load(const json& doc, const dhr::SceneLoadOptions& options = {}) {
  return load_text(doc.dump(), options);
}

// The load fails, and the error names the file and contains `phrase`.
void expect_error(const dhr::SceneLoadResult& r, const std::string& phrase) {
  ASSERT_FALSE(r.ok()) << "loaded, but expected an error containing: " << phrase;
  EXPECT_EQ(r.error.rfind("broken.gltf: ", 0), 0u) << r.error;
  EXPECT_NE(r.error.find(phrase), std::string::npos) << "error: " << r.error << "\nexpected phrase: " << phrase;
}

TEST(SceneMalformed, TheBaseDocumentLoads) {
  auto r = load(valid());
  ASSERT_TRUE(r) << r.error;
  EXPECT_EQ(r.scene->triangle_count, 1u);
}

TEST(SceneMalformed, RejectsGarbageAndTruncatedContainers) {
  expect_error(load_text(""), "empty");
  expect_error(load_text("not json at all"), "not valid glTF JSON");
  expect_error(load_text("[1, 2, 3]"), "not a JSON object");
  expect_error(load_text("{\"asset\": {\"version\": \"1.0\"}}"), "need 2.x");
  expect_error(load_text("{}"), "asset: required but missing");
  expect_error(load_text(std::string(100000, '[')), "nested more than");
  const std::string glb_magic_only = std::string("glTF\x02\x00\x00\x00", 8);
  expect_error(load_text(glb_magic_only), ".glb header truncated");
  std::string glb(20, '\0');
  std::memcpy(glb.data(), "glTF\x02\x00\x00\x00\xff\x00\x00\x00", 12);  // claims 255 bytes
  expect_error(load_text(glb), ".glb truncated");
  std::memcpy(glb.data() + 4, "\x01", 1);
  expect_error(load_text(glb), "version 1");
}

TEST(SceneMalformed, RejectsMissingFilesAndDirectories) {
  auto missing = dhr::load_scene("/nonexistent/scene.gltf");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error, "/nonexistent/scene.gltf: file not found");
  const std::string dir = testing::TempDir();
  auto directory = dhr::load_scene(dir);
  ASSERT_FALSE(directory);
  EXPECT_NE(directory.error.find("not a regular file"), std::string::npos) << directory.error;
}

TEST(SceneMalformed, RejectsFilesOverTheSizeLimit) {
  dhr::SceneLoadOptions options;
  options.max_file_bytes = 100;
  expect_error(load(valid(), options), "max_file_bytes");
}

TEST(SceneMalformed, RejectsNonFinitePositions) {
  json doc = valid();
  doc["buffers"][0]["uri"] = kNanBuffer;
  expect_error(load(doc), "POSITION (accessor 0) has a non-finite value at vertex 1");
}

TEST(SceneMalformed, RejectsOutOfRangeIndices) {
  json doc = valid();
  doc["accessors"][0]["count"] = 2;  // indices still reference vertex 2
  expect_error(load(doc), "1 of 3 indices are out of range (index 2 at position 2, but only 2 vertices)");
}

TEST(SceneMalformed, RejectsIndexAndVertexCountsNotDivisibleByThree) {
  json doc = valid();
  doc["accessors"][1]["count"] = 2;
  expect_error(load(doc), "a triangle list needs a multiple of 3 indices, but has 2");
  doc = valid();
  doc["meshes"][0]["primitives"][0].erase("indices");
  doc["accessors"][0]["count"] = 2;
  expect_error(load(doc), "a triangle list needs a multiple of 3 vertices, but has 2");
}

TEST(SceneMalformed, RejectsAccessorsAndViewsPastTheirStorage) {
  json doc = valid();
  doc["accessors"][0]["count"] = 4;
  expect_error(load(doc),
               "accessors[0]: accessor data (offset 0, stride 12, count 4) runs past the end of bufferView 0");
  doc = valid();
  doc["accessors"][0]["byteOffset"] = 4;
  expect_error(load(doc), "runs past the end of bufferView 0");
  doc = valid();
  doc["bufferViews"][0]["byteStride"] = 16;
  expect_error(load(doc), "runs past the end of bufferView 0");
  doc = valid();
  doc["bufferViews"][1]["byteOffset"] = 40;
  expect_error(load(doc), "bufferViews[1]: range [40, 52) is past the end of buffer 0 (48 bytes)");
  doc = valid();
  doc["buffers"][0]["byteLength"] = 64;  // the data URI holds 48
  expect_error(load(doc), "tinygltf could not load it");
}

TEST(SceneMalformed, RejectsBadReferences) {
  json doc = valid();
  doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7;
  expect_error(load(doc), "attributes.POSITION: refers to accessor 7, but there are 2");
  doc = valid();
  doc["nodes"][0]["mesh"] = 3;
  expect_error(load(doc), "nodes[0].mesh: refers to mesh 3, but there are 1");
  doc = valid();
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  expect_error(load(doc), "refers to material 0, but there are 0");
  doc = valid();
  doc["scenes"][0]["nodes"] = {5};
  expect_error(load(doc), "scenes[0].nodes[0]: is not a valid node index (5)");
  doc = valid();
  doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
  expect_error(load(doc), "has no POSITION attribute");
  doc = valid();
  doc["accessors"][1]["componentType"] = 5126;
  expect_error(load(doc), "cannot hold indices");
  doc = valid();
  doc["accessors"][0]["type"] = "VEC2";
  expect_error(load(doc), "has type VEC2, expected 3 components");
}

TEST(SceneMalformed, RejectsBrokenHierarchies) {
  json doc = valid();
  doc["nodes"] = json::parse(R"([{"children": [1]}, {"children": [2]}, {"children": [0], "mesh": 0}])");
  expect_error(load(doc), "node cycle: ");
  doc["nodes"] = json::parse(R"([{"children": [0]}])");
  expect_error(load(doc), "is its own child");
  doc["nodes"] = json::parse(R"([{"children": [2]}, {"children": [2]}, {"mesh": 0}])");
  doc["scenes"][0]["nodes"] = {0, 1};
  expect_error(load(doc), "nodes[2]: is a child of both node 0 and node 1");
  doc["nodes"] = json::parse(R"([{"children": [1]}, {"mesh": 0}])");
  doc["scenes"][0]["nodes"] = {0, 1};
  expect_error(load(doc), "node 1 is reached twice from scene 0");
  doc = valid();
  doc["nodes"][0]["children"] = {9};
  expect_error(load(doc), "nodes[0].children[0]: is not a valid node index (9)");
}

TEST(SceneMalformed, RejectsMissingScenes) {
  json doc = valid();
  doc.erase("scenes");
  expect_error(load(doc), "the file has no scenes");
  doc = valid();
  doc["scene"] = 2;
  expect_error(load(doc), "scene: refers to scene 2, but there are 1");
  doc = valid();
  doc["scenes"][0]["nodes"] = json::array();
  expect_error(load(doc), "scenes[0]: the scene to show has no nodes");
}

TEST(SceneMalformed, RejectsWrongJsonTypes) {
  json doc = valid();
  doc["nodes"][0]["translation"] = {1, "two", 3};
  expect_error(load(doc), "nodes[0].translation[1]: expected a number, got a string");
  doc = valid();
  doc["nodes"][0]["rotation"] = {0, 0, 1};
  expect_error(load(doc), "nodes[0].rotation: expected 4 numbers, got 3");
  doc = valid();
  doc["accessors"][0]["count"] = -3;
  expect_error(load(doc), "accessors[0].count: expected a non-negative integer, got -3");
  doc = valid();
  doc["accessors"][0]["count"] = 1.5;
  expect_error(load(doc), "accessors[0].count: expected a non-negative integer, got 1.5");
  doc = valid();
  doc["nodes"] = json::object();
  expect_error(load(doc), "nodes: expected an array, got an object");
  doc = valid();
  doc["nodes"][0]["extensions"] = {{"KHR_lights_punctual", 3}};
  expect_error(load(doc), "nodes[0].extensions.KHR_lights_punctual: expected an object, got a number");
  doc = valid();
  doc["meshes"][0]["primitives"][0]["mode"] = 9;
  expect_error(load(doc), "mode: value 9 out of range [0, 6]");
}

TEST(SceneMalformed, RejectsUnsupportedRequiredExtensionsOnly) {
  json doc = valid();
  doc["extensionsRequired"] = {"KHR_texture_transform", "EXT_meshopt_compression"};
  expect_error(load(doc), "required extension EXT_meshopt_compression is not supported");
  doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expect_error(load(doc), "KHR_draco_mesh_compression (Draco-compressed meshes) is not supported");
  doc["extensionsRequired"] = {"KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_sheen",
                               "KHR_materials_emissive_strength", "KHR_mesh_quantization"};
  auto r = load(doc);
  EXPECT_TRUE(r) << r.error;
  doc["extensionsUsed"] = {"EXT_whatever"};  // used but not required: fine
  r = load(doc);
  EXPECT_TRUE(r) << r.error;
}

TEST(SceneMalformed, RejectsInvalidLights) {
  json doc = valid();
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::parse(R"([{"type": "area"}])");
  expect_error(load(doc), "unknown light type \"area\"");
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::parse(R"([{"type": "point", "range": -1}])");
  expect_error(load(doc), "range: value -1 out of range");
  doc["extensions"]["KHR_lights_punctual"]["lights"] =
      json::parse(R"([{"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.4}}])");
  expect_error(load(doc), "innerConeAngle must be smaller than outerConeAngle");
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::parse(R"([{"type": "point"}])");
  doc["nodes"][0]["extensions"] = {{"KHR_lights_punctual", {{"light", 1}}}};
  expect_error(load(doc), "refers to light 1, but there are 1");
}

TEST(SceneMalformed, HugeCountsHitTheBudgetBeforeAllocating) {
  json doc = valid();
  // An accessor with no bufferView is legal (zeros); a count of 4e9 must not allocate 48 GB.
  doc["accessors"][0] = {{"componentType", 5126}, {"count", 3999999999ull}, {"type", "VEC3"}};
  doc["meshes"][0]["primitives"][0].erase("indices");
  expect_error(load(doc), "exceeds the triangle limit (max_triangles");
  dhr::SceneLoadOptions options;
  options.max_triangles = 0;
  expect_error(load(valid(), options), "max_triangles");
}

TEST(SceneMalformed, ExternalBuffersMustExistWithTheirLength) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "dhr_scene_malformed";
  std::filesystem::create_directories(dir);
  json doc = valid();
  doc["buffers"][0]["uri"] = "missing.bin";
  const std::string text = doc.dump();
  auto r = dhr::load_scene_from_memory(text.data(), text.size(), dir.string(), "broken.gltf");
  expect_error(r, "buffers[0]: file 'missing.bin' not found");
  std::ofstream(dir / "short.bin", std::ios::binary) << "0123456789";
  doc["buffers"][0]["uri"] = "short.bin";
  const std::string text2 = doc.dump();
  r = dhr::load_scene_from_memory(text2.data(), text2.size(), dir.string(), "broken.gltf");
  expect_error(r, "buffers[0]: file 'short.bin' has 10 bytes, but byteLength is 48");
}

// The base document as a .glb (JSON chunk + BIN chunk).
std::string make_glb() {
  json doc = valid();
  doc["buffers"][0].erase("uri");
  std::string json_text = doc.dump();
  while (json_text.size() % 4) json_text += ' ';
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t indices[3] = {0, 1, 2};
  const std::string bin = std::string(reinterpret_cast<const char*>(positions), sizeof positions) +
                          std::string(reinterpret_cast<const char*>(indices), sizeof indices);
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(28 + json_text.size() + bin.size())) +
         u32(static_cast<std::uint32_t>(json_text.size())) + "JSON" + json_text +
         u32(static_cast<std::uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
}

TEST(SceneMalformed, EveryTruncationOfAGlbFailsCleanly) {
  // A valid .glb of the base document, then every prefix of it: errors, never crashes.
  const std::string glb = make_glb();
  auto full = dhr::load_scene_from_memory(glb.data(), glb.size(), ".", "broken.glb");
  ASSERT_TRUE(full) << full.error;
  EXPECT_EQ(full.scene->triangle_count, 1u);
  for (std::size_t n = 0; n < glb.size(); ++n) {
    auto r = dhr::load_scene_from_memory(glb.data(), n, ".", "broken.glb");
    EXPECT_FALSE(r.ok()) << "prefix of " << n << " bytes loaded";
    EXPECT_EQ(r.error.rfind("broken.glb: ", 0), 0u) << r.error;
  }
}

TEST(SceneMalformed, RandomByteMutationsNeverCrash) {
  // Seeded, so every run checks the same 3000 mutants of the .glb and of the JSON text.
  std::mt19937 rng(20240611u);
  const std::string originals[2] = {make_glb(), valid().dump()};
  int loaded = 0;
  for (const std::string& original : originals) {
    for (int i = 0; i < 1500; ++i) {
      std::string m = original;
      const int edits = 1 + static_cast<int>(rng() % 6);
      for (int k = 0; k < edits && !m.empty(); ++k) {
        const std::size_t pos = rng() % m.size();
        switch (rng() % 3) {
          case 0:
            m[pos] = static_cast<char>(rng());
            break;
          case 1:
            m[pos] = "0123456789-[]{}\":,e"[rng() % 19];
            break;
          default:
            m.erase(pos, 1 + rng() % 8);
            break;
        }
      }
      auto r = dhr::load_scene_from_memory(m.data(), m.size(), ".", "broken.gltf");
      if (r) {
        ++loaded;
        for (const auto& mesh : r.scene->meshes) {
          for (std::uint32_t index : mesh.indices) ASSERT_LT(index, mesh.positions.size());
        }
      } else {
        ASSERT_EQ(r.error.rfind("broken.gltf: ", 0), 0u) << r.error;
      }
    }
  }
  EXPECT_GT(loaded, 0);  // some mutants (e.g. in vertex data) are still valid files
}

}  // namespace
