// Scene loader on small glTF files written by the tests themselves: transforms, primitive modes,
// normals, texture transforms, instancing, limits and malformed input. Needs no external data.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "test_gltf.hpp"

namespace {

using nlohmann::json;

// The shared builder (tests/common/test_gltf.hpp) with this file's mesh helpers.
class TestGltf : public dhr::test::TestGltf {
 public:
  using dhr::test::TestGltf::accessor;
  int vec3(const std::vector<float>& v) { return floats(v, "VEC3", 3); }
  int indices(const std::vector<std::uint32_t>& v) {
    return accessor(view(v.data(), v.size() * 4), 5125, v.size(), "SCALAR");
  }
  // A mesh with one primitive; returns the mesh index.
  int mesh(json attributes, int indices_accessor = -1, int mode = 4, int material = -1) {
    json prim = {{"attributes", attributes}, {"mode", mode}};
    if (indices_accessor >= 0) prim["indices"] = indices_accessor;
    if (material >= 0) prim["material"] = material;
    doc["meshes"].push_back({{"primitives", json::array({prim})}});
    return static_cast<int>(doc["meshes"].size()) - 1;
  }
};

dhr::SceneLoadResult load(const std::string& text, const dhr::SceneLoadOptions& options = {}) {
  return dhr::load_scene_from_memory(text.data(), text.size(), ".", "test.gltf", options);
}

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

bool has_warning(const dhr::Scene& scene, const std::string& phrase) {
  for (const auto& w : scene.warnings) {
    if (w.find(phrase) != std::string::npos) return true;
  }
  return false;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(SceneSynthetic, ComposesParentTrsWithChildMatrix) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}});
  // Parent: translate (1,2,3), rotate 90 degrees about +Y, scale 2. Child: matrix translating (0,0,1).
  const double s = std::sqrt(0.5);
  g.node({{"children", {1}}, {"translation", {1, 2, 3}}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}});
  g.node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1}}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->meshes.size(), 1u);
  const auto& m = r.scene->meshes[0];
  // world = T(1,2,3) * Ry(90) * S(2) * T(0,0,1) * p; Ry(90) maps x -> -z and z -> x.
  auto expected = [](glm::vec3 p) {
    p.z += 1.0f;
    p *= 2.0f;
    return glm::vec3(1.0f + p.z, 2.0f + p.y, 3.0f - p.x);
  };
  ASSERT_EQ(m.triangle_count(), 1u);
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 local(kTriangle[3 * k], kTriangle[3 * k + 1], kTriangle[3 * k + 2]);
    expect_near(m.positions[m.indices[k]], expected(local));
  }
  EXPECT_EQ(m.node, 1u);
  const glm::dvec4 origin = m.T_world_local * glm::dvec4(0, 0, 0, 1);
  EXPECT_NEAR(origin.x, 1.0 + 2.0, 1e-12);  // child origin (0,0,1) scaled by 2, rotated onto +x
  EXPECT_NEAR(origin.z, 3.0, 1e-12);
}

TEST(SceneSynthetic, NormalsUseTheInverseTransposeAndStayUnit) {
  TestGltf g;
  const float n = 1.0f / std::sqrt(2.0f);
  // A 45-degree slope x + y = 1 with its normal (1,1,0)/sqrt(2), stretched by 4 along y.
  const int mesh =
      g.mesh({{"POSITION", g.vec3({1, 0, 0, 0, 1, 0, 1, 0, -1})}, {"NORMAL", g.vec3({n, n, 0, n, n, 0, n, n, 0})}});
  g.node({{"mesh", mesh}, {"scale", {1, 4, 1}}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  const auto& m = r.scene->meshes[0];
  // The stretched plane is x + y/4 = 1: normal (1, 1/4, 0) normalized.
  const glm::vec3 expected = glm::normalize(glm::vec3(1.0f, 0.25f, 0.0f));
  for (const auto& normal : m.normals) expect_near(normal, expected);
}

TEST(SceneSynthetic, MirroringTransformKeepsFrontFacesCounterClockwise) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}, {"NORMAL", g.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1})}});
  g.node({{"mesh", mesh}, {"scale", {-1, 1, 1}}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  const auto& m = r.scene->meshes[0];
  const glm::vec3 face = glm::cross(m.positions[m.indices[1]] - m.positions[m.indices[0]],
                                    m.positions[m.indices[2]] - m.positions[m.indices[0]]);
  EXPECT_GT(glm::dot(face, m.normals[0]), 0.0f);
  expect_near(m.normals[0], glm::vec3(0, 0, 1));
}

TEST(SceneSynthetic, ConvertsStripsAndFansToLists) {
  // Five vertices: a strip gives 3 triangles with alternating order, a fan 3 triangles around vertex 0.
  const std::vector<float> five = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
  for (int mode : {5, 6}) {
    TestGltf g;
    const int mesh = g.mesh({{"POSITION", g.vec3(five)}}, g.indices({0, 1, 2, 3, 4}), mode);
    g.node({{"mesh", mesh}});
    auto r = load(g.text());
    ASSERT_TRUE(r) << r.error;
    EXPECT_EQ(r.scene->triangle_count, 3u);
    const auto& m = r.scene->meshes[0];
    // No NORMAL: flat normals, unwelded, so positions come per corner; recover the original ids.
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i : m.indices) {
      for (std::uint32_t v = 0; v < 5; ++v) {
        if (m.positions[i] == glm::vec3(five[3 * v], five[3 * v + 1], five[3 * v + 2])) ids.push_back(v);
      }
    }
    const std::vector<std::uint32_t> expected = mode == 5 ? std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}
                                                          : std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0};
    EXPECT_EQ(ids, expected) << "mode " << mode;
    EXPECT_EQ(mode == 5 ? r.scene->stats.strips_converted : r.scene->stats.fans_converted, 1u);
  }
}

TEST(SceneSynthetic, GeneratesFlatNormalsWhenAbsent) {
  TestGltf g;
  // Two triangles sharing an edge at a right angle: flat normals differ per face.
  const int mesh = g.mesh({{"POSITION", g.vec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1})}}, g.indices({0, 1, 2, 0, 1, 3}));
  g.node({{"mesh", mesh}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  const auto& m = r.scene->meshes[0];
  EXPECT_EQ(r.scene->stats.meshes_with_generated_normals, 1u);
  ASSERT_EQ(m.positions.size(), 6u);  // unwelded
  for (int k = 0; k < 3; ++k) expect_near(m.normals[m.indices[k]], glm::vec3(0, 0, 1));
  for (int k = 3; k < 6; ++k) expect_near(m.normals[m.indices[k]], glm::vec3(0, 1, 0));
}

TEST(SceneSynthetic, InstancesShareGeometryIds) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}});
  g.node({{"mesh", mesh}, {"translation", {5, 0, 0}}});
  g.node({{"mesh", mesh}, {"translation", {0, 0, -5}}, {"scale", {2, 2, 2}}});
  auto r = load(g.text({0, 1}));
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->meshes.size(), 2u);
  const auto& a = r.scene->meshes[0];
  const auto& b = r.scene->meshes[1];
  EXPECT_EQ(a.geometry, b.geometry);
  EXPECT_EQ(a.indices, b.indices);
  // Local positions are recoverable from either instance.
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    const glm::dvec3 la = glm::inverse(a.T_world_local) * glm::dvec4(glm::dvec3(a.positions[i]), 1.0);
    const glm::dvec3 lb = glm::inverse(b.T_world_local) * glm::dvec4(glm::dvec3(b.positions[i]), 1.0);
    EXPECT_NEAR(glm::length(la - lb), 0.0, 1e-6);
  }
  EXPECT_EQ(r.scene->triangle_count, 2u);
}

TEST(SceneSynthetic, PicksTheDefaultSceneOrSceneZero) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}});
  g.node({{"mesh", mesh}, {"translation", {10, 0, 0}}});
  g.node({{"mesh", mesh}, {"translation", {20, 0, 0}}});
  g.doc["scenes"] = json::array({{{"nodes", {0}}}, {{"nodes", {1}}}});
  auto first = load(g.text());
  ASSERT_TRUE(first) << first.error;
  EXPECT_FLOAT_EQ(first.scene->bounds.min.x, 10.0f);
  g.doc["scene"] = 1;
  auto second = load(g.text());
  ASSERT_TRUE(second) << second.error;
  EXPECT_FLOAT_EQ(second.scene->bounds.min.x, 20.0f);
}

TEST(SceneSynthetic, AppliesTheBaseColourTextureTransformAndDecodesImages) {
  TestGltf g;
  // 2x1 RGBA PNG: opaque red, half-transparent green.
  g.doc["images"] = json::array({{{"uri",
                                   "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAYAAAD0In+KAAAAD0lEQVR4"
                                   "nGP4z8DwHwgbABB5A359Y87XAAAAAElFTkSuQmCC"}}});
  g.doc["samplers"] = json::array({{{"wrapS", 33071}, {"wrapT", 33648}}});
  g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  json info = {
      {"index", 0},
      {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"scale", {2, 3}}, {"rotation", 0}}}}}};
  g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", info}}}, {"doubleSided", true}}});
  const int mesh =
      g.mesh({{"POSITION", g.vec3(kTriangle)}, {"TEXCOORD_0", g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2)}}, -1, 4, 0);
  g.node({{"mesh", mesh}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->images.size(), 1u);
  const auto& image = r.scene->images[0];
  EXPECT_EQ(image.width, 2u);
  EXPECT_EQ(image.height, 1u);
  EXPECT_EQ(image.rgba8, (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 128}));
  const auto& mat = r.scene->materials[0];
  EXPECT_EQ(mat.base_color_image, 0);
  EXPECT_TRUE(mat.double_sided);
  EXPECT_EQ(mat.wrap_s, dhr::TextureWrap::kClampToEdge);
  EXPECT_EQ(mat.wrap_t, dhr::TextureWrap::kMirroredRepeat);
  EXPECT_TRUE(mat.base_color_uv_transform.present);
  const auto& m = r.scene->meshes[0];
  ASSERT_EQ(m.texcoords.size(), m.positions.size());
  // uv' = offset + scale * uv (no rotation); find the corner that was (1,0): it maps to (2.5, 0.25).
  bool found = false;
  for (const auto& uv : m.texcoords) found = found || (std::abs(uv.x - 2.5f) < 1e-6f && std::abs(uv.y - 0.25f) < 1e-6f);
  EXPECT_TRUE(found);
}

TEST(SceneSynthetic, SixteenBitGreyImagesBecomeRgba8) {
  TestGltf g;
  g.doc["images"] = json::array(
      {{{"uri",
         "data:image/"
         "png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABEAAAAABq7kcWAAAAC0lEQVR4nGNoaAAAAYMBARg1IhUAAAAASUVORK5CYII="}}});
  g.doc["textures"] = json::array({{{"source", 0}}});
  g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  const int mesh =
      g.mesh({{"POSITION", g.vec3(kTriangle)}, {"TEXCOORD_0", g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2)}}, -1, 4, 0);
  g.node({{"mesh", mesh}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->images.size(), 1u);
  EXPECT_EQ(r.scene->images[0].rgba8, (std::vector<std::uint8_t>{128, 128, 128, 255}));
}

TEST(SceneSynthetic, UnusableImagesFallBackToTheColourFactorWithAWarning) {
  TestGltf g;
  // A missing file, and a PNG header claiming 100000 x 100000 pixels (must not be decoded).
  g.doc["images"] =
      json::array({{{"uri", "no_such_image.png"}},
                   {{"uri",
                     "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgABhqAAAYagCAYAAACoUgvIAAAACUlEQVR4nGMAAAABAAFe/"
                     "335AAAAAElFTkSuQmCC"}}});
  g.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  g.doc["materials"] = json::array(
      {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {0.5, 0.25, 1, 1}}}}},
       {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}});
  const int mesh =
      g.mesh({{"POSITION", g.vec3(kTriangle)}, {"TEXCOORD_0", g.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2)}}, -1, 4, 0);
  g.node({{"mesh", mesh}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  EXPECT_TRUE(r.scene->images.empty());
  EXPECT_EQ(r.scene->materials[0].base_color_image, -1);
  EXPECT_EQ(r.scene->materials[0].base_color_factor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
  EXPECT_EQ(r.scene->materials[1].base_color_image, -1);
  EXPECT_TRUE(has_warning(*r.scene, "no_such_image.png"));
  EXPECT_TRUE(has_warning(*r.scene, "100000x100000"));
}

TEST(SceneSynthetic, ReadsNormalizedTexcoordsAndSparseAccessors) {
  TestGltf g;
  const std::vector<std::uint16_t> uv16 = {0, 0, 65535, 0, 0, 32768};
  const int uv = g.accessor(g.view(uv16.data(), uv16.size() * 2), 5123, 3, "VEC2");
  g.doc["accessors"][uv]["normalized"] = true;
  // Sparse: vertex 2 of the triangle is replaced by (0, 5, 0).
  const int pos = g.vec3(kTriangle);
  const std::vector<std::uint8_t> sparse_index = {2, 0, 0, 0};
  const std::vector<float> sparse_value = {0, 5, 0};
  g.doc["accessors"][pos]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", g.view(sparse_index.data(), 4)}, {"componentType", 5121}}},
      {"values", {{"bufferView", g.view(sparse_value.data(), 12)}}}};
  g.doc["images"] = json::array({{{"uri",
                                   "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAYAAAD0In+KAAAAD0lEQVR4"
                                   "nGP4z8DwHwgbABB5A359Y87XAAAAAElFTkSuQmCC"}}});
  g.doc["textures"] = json::array({{{"source", 0}}});
  g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  const int mesh = g.mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, 4, 0);
  g.node({{"mesh", mesh}});
  auto r = load(g.text());
  ASSERT_TRUE(r) << r.error;
  EXPECT_FLOAT_EQ(r.scene->bounds.max.y, 5.0f);
  const auto& m = r.scene->meshes[0];
  bool found = false;
  for (const auto& t : m.texcoords) found = found || (t.x == 1.0f && t.y == 0.0f);
  EXPECT_TRUE(found);
  for (const auto& t : m.texcoords) EXPECT_TRUE(t.y == 0.0f || std::abs(t.y - 32768.0f / 65535.0f) < 1e-6f);
}

TEST(SceneSynthetic, LightsFollowTheirNodes) {
  TestGltf g;
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] =
      json::array({{{"type", "spot"},
                    {"color", {1, 0.5, 0.25}},
                    {"intensity", 40},
                    {"range", 7.5},
                    {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
                   {{"type", "directional"}, {"intensity", 2}},
                   {{"type", "point"}, {"name", "bulb"}}});
  const double s = std::sqrt(0.5);
  // Spot: at (1,2,3) rotated -90 degrees about X, so its -Z points down (-Y).
  g.node({{"translation", {1, 2, 3}},
          {"rotation", {-s, 0, 0, s}},
          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // Directional: rotated 90 degrees about Y, so -Z becomes -X.
  g.node({{"rotation", {0, s, 0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  // Point light on a child of a translated parent.
  g.node({{"translation", {0, 1, 0}}, {"children", {3}}});
  g.node({{"translation", {0, 0, -2}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  auto r = load(g.text({0, 1, 2}));
  ASSERT_TRUE(r) << r.error;
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_FALSE(r.scene->default_lights);
  EXPECT_EQ(lights[0].type, dhr::SceneLight::Type::kSpot);
  expect_near(lights[0].position, glm::vec3(1, 2, 3));
  expect_near(lights[0].direction, glm::vec3(0, -1, 0));
  expect_near(lights[0].color, glm::vec3(1, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(lights[0].intensity, 40.0f);
  EXPECT_FLOAT_EQ(lights[0].range, 7.5f);
  EXPECT_FLOAT_EQ(lights[0].inner_cone, 0.2f);
  EXPECT_FLOAT_EQ(lights[0].outer_cone, 0.6f);
  EXPECT_EQ(lights[1].type, dhr::SceneLight::Type::kDirectional);
  expect_near(lights[1].direction, glm::vec3(-1, 0, 0));
  EXPECT_FLOAT_EQ(lights[1].range, 0.0f);  // absent = infinite
  EXPECT_EQ(lights[2].name, "bulb");
  expect_near(lights[2].position, glm::vec3(0, 1, -2));
  EXPECT_TRUE(has_warning(*r.scene, "no triangles"));
}

TEST(SceneSynthetic, KeepsTheFirst256LightsWithAWarning) {
  TestGltf g;
  for (int i = 0; i < 257; ++i) {
    g.doc["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "point"}});
    g.node({{"translation", {i, 0, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
  }
  std::vector<int> roots(257);
  for (int i = 0; i < 257; ++i) roots[static_cast<std::size_t>(i)] = i;
  auto r = load(g.text(roots));
  ASSERT_TRUE(r) << r.error;
  EXPECT_EQ(r.scene->lights.size(), dhr::kMaxSceneLights);
  EXPECT_EQ(r.scene->stats.lights_dropped, 1u);
  EXPECT_FLOAT_EQ(r.scene->lights.back().position.x, 255.0f);
  EXPECT_TRUE(has_warning(*r.scene, "keeping the first 256"));
}

TEST(SceneSynthetic, UsesTheDefaultRigOnlyWhenAskedAndNoLights) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}});
  g.node({{"mesh", mesh}});
  const std::string text = g.text();
  auto with_rig = load(text);
  ASSERT_TRUE(with_rig) << with_rig.error;
  EXPECT_TRUE(with_rig.scene->default_lights);
  EXPECT_EQ(with_rig.scene->lights.size(), 3u);
  dhr::SceneLoadOptions options;
  options.default_lights_when_none = false;
  auto without = load(text, options);
  ASSERT_TRUE(without) << without.error;
  EXPECT_TRUE(without.scene->lights.empty());
  EXPECT_FALSE(without.scene->default_lights);
}

}  // namespace

// DESIGN 5b: what a file asks for and the loader does not implement is named in a warning, never dropped silently;
// the light extents it does implement (extras.radius, extras.angle, EXT_lights_area) are read without a warning.
TEST(SceneSynthetic, LightExtentsAreReadAndUnimplementedExtensionsNamed) {
  TestGltf g;
  const int mesh = g.mesh({{"POSITION", g.vec3(kTriangle)}});
  g.doc["extensionsUsed"] = {"KHR_lights_punctual", "EXT_lights_area", "EXT_meshopt_compression"};
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"name", "bulb"}, {"intensity", 5.0}, {"extras", {{"radius", 0.06}}}},
      {{"type", "directional"}, {"name", "sun"}, {"extras", {{"angle", 0.0093}}}}};
  g.doc["extensions"]["EXT_lights_area"]["lights"] = {{{"type", "rect"}, {"size", 1.0}, {"rect", {{"aspect", 2.5}}}}};
  g.node({{"mesh", mesh}});
  g.node({{"translation", {0, 2, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  g.node({{"translation", {0, 2.5, 0}}, {"extensions", {{"EXT_lights_area", {{"light", 0}}}}}});
  auto r = load(g.text({0, 1, 2, 3}));
  ASSERT_TRUE(r) << r.error;
  ASSERT_EQ(r.scene->lights.size(), 3u);
  EXPECT_FLOAT_EQ(r.scene->lights[0].radius, 0.06f);
  EXPECT_FLOAT_EQ(r.scene->lights[1].angle, 0.0093f);
  EXPECT_EQ(r.scene->lights[2].type, dhr::SceneLight::Type::kRect);
  EXPECT_TRUE(has_warning(*r.scene, "extension EXT_meshopt_compression is used but not implemented"));
  EXPECT_FALSE(has_warning(*r.scene, "EXT_lights_area"));
  EXPECT_FALSE(has_warning(*r.scene, "extras."));
  EXPECT_FALSE(has_warning(*r.scene, "extension KHR_lights_punctual"));
}
