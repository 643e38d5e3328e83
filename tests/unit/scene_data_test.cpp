// Scene loader on the team's test data (../shared/data, see its MANIFEST.md): every malformed file of
// gltf-bad with its expected outcome, the valid references, and the real scenes with their triangle
// and light counts. Skipped, with the reason, when the data directory is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/geometric.hpp>
#include <string>

#include "scene/scene.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kData = DHR_SHARED_DATA_DIR;

#define REQUIRE_DATA(relative)                                                         \
  do {                                                                                 \
    if (!fs::exists(kData / (relative))) {                                             \
      GTEST_SKIP() << "test data not available: " << (kData / (relative)).string()     \
                   << " (the shared data directory is optional; these tests need it)"; \
    }                                                                                  \
  } while (0)

bool has_warning(const dhr::Scene& scene, const std::string& phrase) {
  for (const auto& w : scene.warnings) {
    if (w.find(phrase) != std::string::npos) return true;
  }
  return false;
}

// What every loaded scene must satisfy, whatever the file.
void check_invariants(const dhr::Scene& scene) {
  std::uint64_t triangles = 0;
  for (const auto& m : scene.meshes) {
    ASSERT_EQ(m.normals.size(), m.positions.size()) << m.name;
    ASSERT_TRUE(m.texcoords.empty() || m.texcoords.size() == m.positions.size()) << m.name;
    ASSERT_EQ(m.indices.size() % 3, 0u) << m.name;
    ASSERT_LT(m.material, scene.materials.size()) << m.name;
    for (std::uint32_t i : m.indices) ASSERT_LT(i, m.positions.size()) << m.name;
    for (const auto& p : m.positions) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    for (const auto& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f) << m.name;
    triangles += m.triangle_count();
  }
  EXPECT_EQ(triangles, scene.triangle_count);
  for (const auto& mat : scene.materials) {
    ASSERT_LT(mat.base_color_image, static_cast<int>(scene.images.size()));
  }
  for (const auto& image : scene.images) {
    ASSERT_EQ(image.rgba8.size(), std::size_t{image.width} * image.height * 4) << image.name;
  }
  EXPECT_LE(scene.lights.size(), dhr::kMaxSceneLights);
  for (const auto& l : scene.lights) EXPECT_FALSE(dhr::validate_light(l).has_value()) << l.name;
}

dhr::SceneLoadResult load(const std::string& relative) { return dhr::load_scene((kData / relative).string()); }

struct BadCase {
  const char* path;
  const char* phrase;
};

class SceneBadFile : public testing::TestWithParam<BadCase> {};

TEST_P(SceneBadFile, IsRejectedWithAClearError) {
  const BadCase& c = GetParam();
  REQUIRE_DATA(c.path);
  const std::string full = (kData / c.path).string();
  auto r = dhr::load_scene(full);
  ASSERT_FALSE(r.ok()) << c.path << " loaded";
  EXPECT_EQ(r.error.rfind(full + ": ", 0), 0u) << "the error must start with the file: " << r.error;
  EXPECT_NE(r.error.find(c.phrase), std::string::npos) << r.error << "\nexpected phrase: " << c.phrase;
}

INSTANTIATE_TEST_SUITE_P(
    GltfBad, SceneBadFile,
    testing::Values(
        BadCase{"gltf-bad/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
                "POSITION (accessor 2) has a non-finite value"},
        BadCase{"gltf-bad/IndexOutOfRange/IndexOutOfRange.gltf", "1 of 36 indices are out of range"},
        BadCase{"gltf-bad/IndexOutOfRange/AllIndicesOutOfRange.gltf", "36 of 36 indices are out of range"},
        BadCase{"gltf-bad/MissingBin/BoxTextured.gltf", "buffers[0]: file 'BoxTextured0.bin' not found"},
        BadCase{"gltf-bad/wrongTypes/badArray.gltf", "meshes[0].primitives: expected an array, got an object"},
        BadCase{"gltf-bad/wrongTypes/badObject.gltf",
                "materials[0].pbrMetallicRoughness: expected an object, got an array"},
        BadCase{"gltf-bad/wrongTypes/badNumber.gltf",
                "materials[0].normalTexture.scale: expected a number, got a string"},
        BadCase{"gltf-bad/wrongTypes/badString.gltf", "scenes[0].name: expected a string, got a number"},
        BadCase{"gltf-bad/wrongTypes/badUint.gltf", "baseColorTexture.index: expected a non-negative integer, got -1"},
        BadCase{"gltf-bad/wrongTypes/badExtension.gltf",
                "baseColorTexture.extensions.KHR_texture_transform: expected an object, got a string"},
        BadCase{"gltf-bad/SchemaFailures/sceneWrongType.gltf", "scene: expected a non-negative integer, got a string"},
        BadCase{"gltf-bad/RecursiveNodes/RecursiveNodes.gltf", "node cycle: 1 -> 0 -> 1"},
        BadCase{"gltf-bad/TestNoRootNode/NoScene.gltf", "the file has no scenes"},
        BadCase{"gltf-bad/TestNoRootNode/SceneWithoutNodes.gltf", "scenes[0]: the scene to show has no nodes"},
        // Its buffer views (1800 bytes) overrun its 514-byte buffer before the 35-vertex lists matter.
        BadCase{"gltf-bad/IncorrectVertexArrays/Cube.gltf",
                "bufferViews[2]: range [504, 936) is past the end of buffer 0"},
        BadCase{"gltf-bad/draco/2CylinderEngine.gltf",
                "KHR_draco_mesh_compression (Draco-compressed meshes) is not supported"},
        BadCase{"gltf-bad/BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf",
                "required extension KHR_technique_webgl is not supported"}));

TEST(SceneDataLoadsWithWarnings, BoxBadNormalsAreRenormalizedOrRepaired) {
  REQUIRE_DATA("gltf-bad/BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
  auto r = load("gltf-bad/BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
  ASSERT_TRUE(r) << r.error;
  check_invariants(*r.scene);
  EXPECT_EQ(r.scene->triangle_count, 12u);
  EXPECT_EQ(r.scene->stats.normals_renormalized, 4u);  // length 0.1
  EXPECT_EQ(r.scene->stats.normals_repaired, 4u);      // length 0
  EXPECT_TRUE(has_warning(*r.scene, "4 normals were not unit length; renormalized"));
  EXPECT_TRUE(has_warning(*r.scene, "4 normals were zero or not finite; replaced by face normals"));
  // Repaired normals agree with their faces.
  for (const auto& m : r.scene->meshes) {
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const glm::vec3 face = glm::cross(m.positions[m.indices[t + 1]] - m.positions[m.indices[t]],
                                        m.positions[m.indices[t + 2]] - m.positions[m.indices[t]]);
      for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(face, m.normals[m.indices[t + k]]), 0.0f);
    }
  }
}

TEST(SceneDataLoadsWithWarnings, Texcoord1WithoutTexcoord0IgnoresTheTexture) {
  REQUIRE_DATA("gltf-bad/issue_3269/texcoord_crash.gltf");
  auto r = load("gltf-bad/issue_3269/texcoord_crash.gltf");
  ASSERT_TRUE(r) << r.error;
  check_invariants(*r.scene);
  EXPECT_EQ(r.scene->triangle_count, 10u);
  EXPECT_TRUE(has_warning(*r.scene, "uses TEXCOORD_0, which the primitive lacks"));
  for (const auto& m : r.scene->meshes) {
    EXPECT_EQ(m.texcoords.empty(), m.name == "TopRightMesh/0" || m.name == "BackPlaneMesh/0") << m.name;
  }
}

TEST(SceneDataLoadsWithWarnings, MissingImageFallsBackToTheColourFactor) {
  REQUIRE_DATA("gltf-bad/BoxTextured-glTF/BoxTextured.gltf");
  // The .gltf and .bin without the .png, in a scratch directory.
  const fs::path dir = fs::path(testing::TempDir()) / "dhr_scene_missing_image";
  fs::create_directories(dir);
  for (const char* f : {"BoxTextured.gltf", "BoxTextured0.bin"}) {
    fs::copy_file(kData / "gltf-bad/BoxTextured-glTF" / f, dir / f, fs::copy_options::overwrite_existing);
  }
  fs::remove(dir / "CesiumLogoFlat.png");
  auto r = dhr::load_scene((dir / "BoxTextured.gltf").string());
  ASSERT_TRUE(r) << r.error;
  check_invariants(*r.scene);
  EXPECT_EQ(r.scene->triangle_count, 12u);
  EXPECT_TRUE(r.scene->images.empty());
  EXPECT_EQ(r.scene->materials[0].base_color_image, -1);
  EXPECT_TRUE(has_warning(*r.scene, "('CesiumLogoFlat.png') could not be read"));
}

TEST(SceneDataReferences, BoxTexturedVariantsLoadWithTheirTexture) {
  for (const char* path :
       {"gltf-bad/BoxTextured-glTF/BoxTextured.gltf", "gltf-bad/BoxTextured-glTF-Binary/BoxTextured.glb",
        "gltf-bad/BoxTextured-glTF-Embedded/BoxTextured.gltf",
        "gltf-bad/BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf"}) {
    REQUIRE_DATA(path);
    auto r = load(path);
    ASSERT_TRUE(r) << r.error;
    check_invariants(*r.scene);
    EXPECT_EQ(r.scene->triangle_count, 12u) << path;
    ASSERT_EQ(r.scene->images.size(), 1u) << path;
    EXPECT_EQ(r.scene->images[0].width, 211u);
    EXPECT_EQ(r.scene->images[0].height, 211u);
    EXPECT_EQ(r.scene->materials[0].base_color_image, 0);
    EXPECT_EQ(r.scene->meshes[0].texcoords.size(), r.scene->meshes[0].positions.size());
    EXPECT_TRUE(r.scene->default_lights);
  }
}

TEST(SceneDataReferences, PrimitiveModesGiveTheExpectedTriangles) {
  // 00-03 and 07-10: points, lines, line loops, line strips (skipped); 04/11 strips, 05/12 fans,
  // 06 and 13-15 lists: each triangle mode draws the same unit quad in the z = 0 plane, facing +Z.
  const int expected[16] = {0, 0, 0, 0, 2, 2, 2, 0, 0, 0, 0, 2, 2, 2, 2, 2};
  for (int i = 0; i < 16; ++i) {
    char path[128];
    std::snprintf(path, sizeof path, "gltf-bad/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf",
                  i);
    REQUIRE_DATA(path);
    auto r = load(path);
    ASSERT_TRUE(r) << r.error;
    check_invariants(*r.scene);
    EXPECT_EQ(r.scene->triangle_count, static_cast<std::uint64_t>(expected[i])) << path;
    const auto& stats = r.scene->stats;
    EXPECT_EQ(stats.point_primitives_skipped, (i == 0 || i == 7) ? 1u : 0u) << path;
    EXPECT_EQ(stats.line_primitives_skipped, ((i >= 1 && i <= 3) || (i >= 8 && i <= 10)) ? 1u : 0u) << path;
    EXPECT_EQ(stats.strips_converted, (i == 4 || i == 11) ? 1u : 0u) << path;
    EXPECT_EQ(stats.fans_converted, (i == 5 || i == 12) ? 1u : 0u) << path;
    if (expected[i] == 0) {
      EXPECT_TRUE(has_warning(*r.scene, "only triangles cast shadows")) << path;
      continue;
    }
    float area = 0.0f;
    for (const auto& m : r.scene->meshes) {
      for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::vec3 c = glm::cross(m.positions[m.indices[t + 1]] - m.positions[m.indices[t]],
                                       m.positions[m.indices[t + 2]] - m.positions[m.indices[t]]);
        EXPECT_GT(c.z, 0.0f) << path << ": triangle " << t / 3 << " faces away";
        area += 0.5f * glm::length(c);
      }
    }
    EXPECT_NEAR(area, 1.0f, 1e-5f) << path;
  }
}

TEST(SceneDataReferences, OtherValidFilesLoad) {
  const std::pair<const char*, std::uint64_t> files[] = {
      {"gltf-bad/textureTransform/TextureTransformTest.gltf", 24},
      {"gltf-bad/cameras/Cameras.gltf", 2},
      {"gltf-bad/ClearCoat-glTF/ClearCoatTest.gltf", 37116},
      {"gltf-bad/simple_skin/simple_skin.gltf", 8},
      {"gltf-bad/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", 12},
      {"gltf-bad/BoxTexcoords-glTF/boxTexcoords.gltf", 12}};
  for (const auto& [path, triangles] : files) {
    REQUIRE_DATA(path);
    auto r = load(path);
    ASSERT_TRUE(r) << r.error;
    check_invariants(*r.scene);
    EXPECT_EQ(r.scene->triangle_count, triangles) << path;
  }
  auto tt = load("gltf-bad/textureTransform/TextureTransformTest.gltf");
  ASSERT_TRUE(tt) << tt.error;
  const auto& offset_u = tt.scene->materials[0];
  EXPECT_EQ(offset_u.name, "Offset U");
  EXPECT_TRUE(offset_u.base_color_uv_transform.present);
  EXPECT_EQ(offset_u.base_color_uv_transform.offset, glm::vec2(0.5f, 0.0f));
  EXPECT_NEAR(tt.scene->materials[3].base_color_uv_transform.rotation, 0.39269908f, 1e-6f);
  EXPECT_TRUE(has_warning(*load("gltf-bad/simple_skin/simple_skin.gltf").scene, "skinning is ignored"));
}

struct RealScene {
  const char* path;
  std::uint64_t triangles;
  std::size_t lights;
  dhr::SceneLight::Type light_type;
  bool default_rig;  // the file has no lights
};

class SceneDataRealScene : public testing::TestWithParam<RealScene> {};

TEST_P(SceneDataRealScene, LoadsWithTheManifestCounts) {
  const RealScene& s = GetParam();
  REQUIRE_DATA(s.path);
  auto r = load(s.path);
  ASSERT_TRUE(r) << r.error;
  check_invariants(*r.scene);
  EXPECT_EQ(r.scene->triangle_count, s.triangles);
  EXPECT_EQ(r.scene->lights.size(), s.lights);
  EXPECT_EQ(r.scene->default_lights, s.default_rig);
  if (!r.scene->default_lights) {
    for (const auto& l : r.scene->lights) EXPECT_EQ(l.type, s.light_type) << l.name;
  }
}

using Type = dhr::SceneLight::Type;
INSTANTIATE_TEST_SUITE_P(
    Scenes, SceneDataRealScene,
    testing::Values(RealScene{"scenes/living_room.glb", 163448, 3, Type::kPoint, false},
                    RealScene{"scenes/living_room_dense.glb", 1203857, 3, Type::kPoint, false},
                    RealScene{"scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf", 6000, 5, Type::kPoint, false},
                    RealScene{"scenes/GlamVelvetSofa/glTF/GlamVelvetSofa.gltf", 4196, 1, Type::kDirectional, false},
                    RealScene{"scenes/SheenChair/glTF/SheenChair.gltf", 39936, 3, Type::kPoint, true},
                    RealScene{"scenes/ToyCar/glTF/ToyCar.gltf", 108936, 3, Type::kPoint, true},
                    RealScene{"scenes/MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf", 1040409, 3,
                              Type::kPoint, true},
                    RealScene{"scenes/Duck/glTF/Duck.gltf", 4212, 3, Type::kPoint, true},
                    RealScene{"scenes/Box/glTF/Box.gltf", 12, 3, Type::kPoint, true}));

TEST(SceneDataRealScene, LivingRoomLightsAndBounds) {
  REQUIRE_DATA("scenes/living_room.glb");
  auto r = load("scenes/living_room.glb");
  ASSERT_TRUE(r) << r.error;
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_FLOAT_EQ(lights[0].intensity, 30.0f);
  EXPECT_FLOAT_EQ(lights[1].intensity, 25.0f);
  EXPECT_FLOAT_EQ(lights[2].intensity, 8.0f);
  EXPECT_EQ(lights[0].name, "Ceiling_Point_A");
  // The 6 x 2.8 x 4 m room with the floor at y = 0.
  EXPECT_NEAR(r.scene->bounds.min.y, 0.0f, 1e-4f);
  EXPECT_NEAR(r.scene->bounds.size().x, 6.0f, 1e-3f);
  EXPECT_NEAR(r.scene->bounds.size().y, 2.8f, 1e-3f);
  EXPECT_NEAR(r.scene->bounds.size().z, 4.0f, 1e-3f);
  EXPECT_FALSE(r.scene->images.empty());
  EXPECT_TRUE(r.scene->warnings.empty()) << r.scene->warnings.front();
}

// MANIFEST: a 1.0 x 0.4 m ceiling panel (rect) and a 0.6 m ceiling disk, both facing down, and the lamp bulb as
// a 6 cm sphere light.
TEST(SceneDataRealScene, LivingRoomAreaLightsHaveTheirExtent) {
  REQUIRE_DATA("scenes/living_room_area.glb");
  auto r = load("scenes/living_room_area.glb");
  ASSERT_TRUE(r) << r.error;
  check_invariants(*r.scene);
  EXPECT_EQ(r.scene->triangle_count, 163448u);
  EXPECT_TRUE(r.scene->warnings.empty()) << r.scene->warnings.front();
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 3u);
  // Node order: the two ceiling lights, then the lamp.
  EXPECT_EQ(lights[0].type, Type::kRect);
  EXPECT_NEAR(lights[0].width, 1.0f, 1e-6f);
  EXPECT_NEAR(lights[0].height, 0.4f, 1e-6f);
  EXPECT_EQ(lights[1].type, Type::kDisk);
  EXPECT_NEAR(lights[1].width, 0.6f, 1e-6f);
  EXPECT_EQ(lights[1].width, lights[1].height);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(glm::length(lights[i].direction - glm::vec3(0, -1, 0)), 0.0f, 1e-6f) << lights[i].name;
    EXPECT_NEAR(lights[i].position.y, 2.55f, 1e-5f);
  }
  EXPECT_EQ(lights[2].type, Type::kPoint);
  EXPECT_FLOAT_EQ(lights[2].radius, 0.06f);
  for (const auto& l : lights) EXPECT_FALSE(dhr::validate_light(l).has_value()) << l.name;
}

// MANIFEST: the 3 room lights and a directional sun with extras.angle 0.0093 rad.
TEST(SceneDataRealScene, LivingRoomSunHasItsAngle) {
  REQUIRE_DATA("scenes/living_room_sun.glb");
  auto r = load("scenes/living_room_sun.glb");
  ASSERT_TRUE(r) << r.error;
  EXPECT_TRUE(r.scene->warnings.empty()) << r.scene->warnings.front();
  const auto& lights = r.scene->lights;
  ASSERT_EQ(lights.size(), 4u);
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(lights[i].has_extent()) << lights[i].name;
  EXPECT_EQ(lights[3].type, Type::kDirectional);
  EXPECT_FLOAT_EQ(lights[3].angle, 0.0093f);
  EXPECT_LT(lights[3].direction.y, 0.0f);  // 40 degrees high: it shines down
}

}  // namespace
