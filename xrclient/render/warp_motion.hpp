// The warp's motion parameters (shader_interface.h's ClientWarpMotion, kClientWarpMotion) from what moved between
// each source's scene time and the display's (scene/scene_motion.hpp), and the rule's CPU reference in double
// (shaders/client/motion_rule.h makes the same decisions in float, display-eye relative).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "scene/scene_motion.hpp"
#include "shaders/shader_interface.h"
#include "visibility/visibility_layout.hpp"

namespace dhr::render {

// Receiver test margin (metres): a surface point this close to a moved mesh's box may lie on it (the boxes bound
// the mesh's vertices exactly; the margin covers float rounding of the display-relative point).
inline constexpr double kMotionReceiverMargin = 0.01;

struct WarpMotionInput {
  const SceneMotion* motion = nullptr;  // null or a scene that does not move: inactive
  double display_time = 0.0;            // seconds: the scene time the frame displays
  std::array<std::optional<double>, 3> source_times;  // each source's traced scene time (none: no source)
  std::span<const SceneLight> lights;   // at the display time (the first layout.light_count are used)
  VisibilityLayout layout;              // the masks' fields
  glm::dvec3 eye{0.0};                  // display eye position (world): everything is made relative to it
  double far_distance = 100.0;          // directional lights: segment length (the scene's bounding diagonal)
  const NodeOverrides* overrides = nullptr;  // app-moved nodes, at every time (the frame's MovedScene::overrides)
};

// Fills `out` (inactive when nothing moves). `scratch` holds the boxes between calls (no allocation once grown).
void make_warp_motion(const WarpMotionInput& input, std::vector<WorldBox>& scratch, shader::ClientWarpMotion& out);

// The bits motion made unknown for source `s` at the display-eye-relative surface point `p` (world axes), as
// motion_rule.h decides. `margin` (optional) gets the smallest distance in metres of p or of a light's segment from
// a box face (how far the decision is from flipping).
uint32_t motion_unknown_bits(const shader::ClientWarpMotion& m, uint32_t s, const glm::dvec3& p, uint32_t light_count,
                             uint32_t unknown_mask, double* margin = nullptr);

}  // namespace dhr::render
