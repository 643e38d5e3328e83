// A small glTF scene with a node an application may move (`extras: {"dhr_movable": true}`, no animation), for the
// tests of app-moved nodes (docs/motion.md): a 8 m x 8 m floor (node 0, y = 0, one-sided, facing +y), a 1 m x 1 m
// double-sided occluder at (-1.5, 1, 0) (node 1, named "Occluder", movable) and a point light at (0, 3, 0) (node 2).
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "math/trs.hpp"
#include "test_gltf.hpp"

namespace dhr::test {

inline constexpr std::uint32_t kFloorNode = 0, kOccluderNode = 1;

inline std::string movable_occluder_gltf() {
  using nlohmann::json;
  TestGltf g;
  const auto quad = [&](float half, int material) {
    const int pos = g.floats({-half, 0, -half, -half, 0, half, half, 0, half, half, 0, -half}, "VEC3", 3);
    const std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
    const int idx = g.accessor(indices.data(), indices.size() * 2, 5123, indices.size(), "SCALAR");
    const json primitive = {{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"material", material}};
    g.doc["meshes"].push_back({{"primitives", json::array({primitive})}});
    return static_cast<int>(g.doc["meshes"].size()) - 1;
  };
  g.doc["materials"] = json::array({{{"doubleSided", false}}, {{"doubleSided", true}}});
  g.node({{"mesh", quad(4.0f, 0)}});
  g.node({{"name", "Occluder"},
          {"mesh", quad(0.5f, 1)},
          {"translation", {-1.5, 1.0, 0.0}},
          {"extras", {{"dhr_movable", true}}}});
  g.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}, {"intensity", 20}}});
  g.doc["extensionsUsed"] = json::array({"KHR_lights_punctual"});
  g.node({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  return g.text({0, 1, 2});
}

// The occluder moved along x (its rest height, orientation and scale).
inline Trs occluder_at(double x) {
  return Trs{glm::dvec3(x, 1.0, 0.0), glm::dquat(1.0, 0.0, 0.0, 0.0), glm::dvec3(1.0)};
}

}  // namespace dhr::test
