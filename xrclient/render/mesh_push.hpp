// The transform part of ClientGBufferPush for one draw, shared by every raster pass that draws a ClientScene
// (G-buffer, forward, shadow maps). A static mesh gets the pass's view-projection (rounded to float once) and
// its camera-relative origin, as before motion existed (the same bits); a moving mesh gets its whole
// model-view-projection at the frame's scene time composed in double, with the camera-relative translation
// (motion * origin - eye) subtracted before anything is rounded, and the motion's normal matrix.
#pragma once
#include <array>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "shaders/shader_interface.h"

namespace dhr::render {

struct ClientMesh;

class MeshPush {
 public:
  // `view_proj`: the pass's view-projection of eye-relative positions (the eye, or the light map's origin, at
  // the origin), in double; `eye`: that origin in world space.
  MeshPush(const glm::dmat4& view_proj, const glm::dvec3& eye);

  // Sets push.view_proj, push.mesh and the kClientMeshMoves bit of push.flags (other bits kept). `motion`:
  // rest world -> world of a moving mesh (MovedScene::motion), null for a static one.
  void set(shader::ClientGBufferPush& push, const ClientMesh& mesh, const glm::dmat4* motion) const;

 private:
  glm::dmat4 view_proj_;
  std::array<float, 16> view_proj_floats_;
  glm::dvec3 eye_;
};

}  // namespace dhr::render
