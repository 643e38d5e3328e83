// The client's own shadow maps: one cube (six 90-degree depth faces) per point or spot light, rendered from
// the ClientScene once at rest (again when the lights change) into one depth atlas, row l for
// light l, faces 0-5 in columns (face conventions: shaders/client/cube_face.h). A sun (a directional light with
// an angle) gets an orthographic tile fitted to the scene's bounds in column 0 of its row (sun_map.hpp); other
// directional lights get none. When the scene moves, update() re-renders, inside the frame's command buffer, the
// faces that moving casters or a moving light made stale (the rule: shadow_refresh.hpp), all of them or each
// light's in its turn (ShadowRefresh); the others stay.
// The warp pass looks them up for pixels no visibility buffer fills (and, with kClientWarpShadowEdges, for
// bits the buffer's samples disagree on); without any server they shade the whole frame (offline, `local`).
//
// Every triangle casts (no culling, alpha ignored), as the server's shadow rays see the scene. Depth is
// reversed-Z with an infinite far plane, near / (distance along the face axis), like the G-buffer.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "plan/shipped_defaults.hpp"
#include "scene/lighting.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class ClientScene;
struct MovedScene;

struct ShadowMapSettings {
  uint32_t size = 1024;          // texels per face side (clamped so the atlas fits the device's limit)
  double near_plane = 0.02;      // metres: geometry nearer to a light does not cast
  double bias_rel = 0.001;       // lit when stored >= distance - (bias_rel * distance + bias_abs + slope term)
  double bias_abs = 0.001;       // metres
  double normal_offset = 0.25;   // texels (at the point's distance) along the normal before the lookup
  double bias_slope = 1.0;       // plus this many texels times tan(angle between normal and light), tan <= 10
  // A moving scene keeps a second atlas of the static casters alone, rendered once: a stale face of a light that
  // does not move is then that copy plus the moving meshes (the same depths as drawing them all), not a re-render.
  bool split_static = true;
  // In a moving scene, where the maps only fill (DHR's frames showing visibility traced for the scene time they
  // show: client::StereoPipeline), each light's map is re-rendered once per this much scene time, in turns
  // (ShadowRefresh); 0: every stale face every frame, as `local` does.
  int64_t fill_period_ns = client::shipped::kShadowFillPeriodNs;
};

// One direction from a light on its cube (the C++ twin of cube_face.h's cube_lookup, in double).
struct CubeLookup {
  uint32_t face = 0;
  glm::ivec2 texel{0};
  double distance = 0.0;     // along the face's axis
  glm::dvec2 position{0.0};  // continuous texel coordinate before clamping
  double margin = 0.0;       // texels / relative distance to the nearest face or texel flip
};
CubeLookup cube_lookup(const glm::dvec3& v, uint32_t size);
double cube_face_distance(const glm::dvec3& v);

// The 90-degree camera of a face at `light` (extent size x size).
Camera cube_face_camera(const glm::dvec3& light, uint32_t face, uint32_t size);

// A sun's orthographic tile (sun_map.hpp): world frame, metres.
struct SunMap {
  glm::dvec3 position{0.0};  // centre of the near plane
  glm::dvec3 right{1.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};  // the map looks along cross(up, right), the light's direction
  double half_extent = 0.0;
  double depth_range = 0.0;
};

// Where a light's map is: row of the atlas, or nullopt (a directional light without an angle: no shadow map).
struct ShadowTile {
  std::optional<uint32_t> row;
  glm::dvec3 position{0.0};  // world: the cube's centre (the light's); a sun: its map's near-plane centre
  std::optional<SunMap> sun;  // a sun (directional with an angle): one orthographic tile in column 0
};

// Which of the stale faces one update() re-renders.
struct ShadowRefresh {
  int64_t scene_time_ns = 0;  // the frame's scene time (the MovedScene's), in integer nanoseconds
  // 0: every stale face now (`local`'s maps, and DHR's wherever they shade whole fields). Otherwise a light's map
  // is re-rendered once per period of scene time, light l at its own phase (l / lights of a period later than
  // light 0), with every face that went stale since it was last rendered; in between its map stays as it was
  // rendered, origin included (tiles()): older, and consistent with itself.
  int64_t period_ns = 0;
  // Every stale face now, whatever the period (the maps shade more than fills this frame); the lights' turns go on
  // from this time as if each had just taken its turn.
  bool all_now = false;
};

// What one update() re-rendered.
struct ShadowUpdate {
  uint32_t lights = 0;  // lights with at least one face re-rendered
  uint32_t faces = 0;   // cube faces (a sun's tile counts as one)
};

class ShadowMaps {
 public:
  // Renders the maps (blocking). Throws std::invalid_argument for settings that cannot work (size 0, near <= 0).
  ShadowMaps(const vk::Context& context, const ClientScene& scene, const ShadowMapSettings& settings = {});

  // Re-renders for new lights (blocking), the scene at rest.
  void render(std::span<const SceneLight> lights);
  // Records into `cmd` (outside any rendering scope) the re-render at `moved`'s scene time of every stale face
  // (shadow_refresh.hpp) and moves the moving lights' maps with them; records nothing when no face is stale (a
  // static scene: never). The lights are moved.lights (the scene's, as the maps were rendered for). The atlas is
  // SHADER_READ_ONLY_OPTIMAL again afterwards, its writes visible to later shader reads; earlier readers of the
  // atlas (previous frames) are waited for.
  // refresh: which stale faces (ShadowRefresh; the default: all of them).
  ShadowUpdate update(VkCommandBuffer cmd, const MovedScene& moved, const ShadowRefresh& refresh = {});

  const ShadowMapSettings& settings() const { return settings_; }
  uint32_t face_size() const { return size_; }
  const std::vector<ShadowTile>& tiles() const { return tiles_; }  // one per light, in order
  vk::Image& atlas() { return atlas_; }  // D32, (6 * size) x (rows * size), SHADER_READ_ONLY_OPTIMAL
  const vk::Image& atlas() const { return atlas_; }
  double render_ms() const { return render_ms_; }  // host time of the last render
  // Per light: the faces (bit f; a sun: bit 0) the last update() re-rendered (0 after render()).
  const std::vector<uint8_t>& updated_faces() const { return stale_; }
  // Per light: the faces older than the last update()'s scene time that something moved in since (waiting for the
  // light's turn: ShadowRefresh); 0 after render() and wherever every stale face was re-rendered.
  const std::vector<uint8_t>& waiting_faces() const { return pending_; }

 private:
  ShadowTile tile_for(const SceneLight& light, std::optional<uint32_t> row) const;
  // Draws face `face` of `tile` (a sun: its tile) with the meshes at `moved`'s time (null: at rest).
  // Which meshes a face draws: all, those that never move (the static atlas), or the moving ones alone.
  enum class Casters : uint8_t { kAll, kStatic, kMoving };
  void draw_face(VkCommandBuffer cmd, const ShadowTile& tile, uint32_t face, const MovedScene* moved,
                 Casters casters = Casters::kAll) const;
  void render_sun(VkCommandBuffer cmd, const ShadowTile& tile, const MovedScene* moved, Casters casters) const;
  bool drawn(uint32_t mesh, Casters casters) const;
  bool takes_turn(size_t light, const ShadowRefresh& refresh);
  // The atlas's rectangle that holds every face update() re-renders (stale_).
  VkRect2D stale_area() const;
  // Copies the static atlas's faces that update() completes with the moving meshes (split_faces_) into the atlas,
  // leaving the atlas in DEPTH_ATTACHMENT_OPTIMAL. False when there are none.
  bool copy_static_faces(VkCommandBuffer cmd);

  const vk::Context* context_;
  const ClientScene* scene_;
  ShadowMapSettings settings_;
  uint32_t size_ = 0;
  vk::PipelineLayout layout_;
  vk::Pipeline pipeline_;
  vk::Image atlas_;
  vk::Image static_atlas_;  // the static casters alone (split_static in a moving scene), TRANSFER_SRC_OPTIMAL
  std::vector<ShadowTile> tiles_;
  std::vector<uint8_t> split_faces_;  // per light: stale faces completed from the static atlas (update())
  std::vector<VkImageCopy> copies_;   // their regions (kept: no allocation per frame)
  std::vector<uint8_t> held_;   // per light: faces that held a moving mesh when last rendered (shadow_refresh.hpp)
  std::vector<uint8_t> stale_;  // per light: faces update() re-renders (kept: no allocation per frame)
  std::vector<uint8_t> pending_;  // per light: faces gone stale since its map was last rendered (waiting its turn)
  std::vector<int64_t> turn_;     // per light: the refresh period its map was last rendered in (ShadowRefresh)
  double render_ms_ = 0.0;
};

// CPU reference of the warp's shadow lookup (double, on a read-back atlas; render/shadow_lookup_reference.cpp).
struct ShadowReference {
  std::span<const float> atlas;  // (6 * face_size) x (rows * face_size), row-major
  uint32_t face_size = 0;
  std::vector<ShadowTile> tiles;
  ShadowMapSettings settings;
};
struct ShadowDecision {
  uint32_t mask = 0;
  uint32_t confident = 0;  // see warp.comp's shadow_lookup
  double margin = 0.0;  // smallest distance to a flip of any decision made (see warp_reference.hpp)
};

// p and n in world space (n unit); lights as in the scene (at most 32); pixel_world: a display pixel's size at p.
ShadowDecision shadow_mask_reference(const ShadowReference& maps, std::span<const SceneLight> lights,
                                     const glm::dvec3& p, const glm::dvec3& n, double pixel_world);

}  // namespace dhr::render
