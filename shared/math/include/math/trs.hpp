// A node's local transform as translation, rotation and scale (glTF's TRS: local = T * R * S), in double. What an
// application sends to move a node at run time (protocol NodeTransform, scene/node_overrides.hpp).
#pragma once
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace dhr {

struct Trs {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // unit
  glm::dvec3 scale{1.0};                    // every component > 0
  bool operator==(const Trs&) const = default;
};

}  // namespace dhr
