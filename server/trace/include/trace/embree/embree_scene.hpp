// The Embree side of a Scene: one Embree 3 device and one flattened triangle scene (one Embree geometry per
// SceneMesh, geometry ID = mesh index), built in coordinates relative to the scene's bounding-box centre
// so that large world offsets keep float precision. Also turns Embree hits into surface points.
//
// A scene with meshes on moving nodes is built with RTC_SCENE_FLAG_DYNAMIC (Embree's two-level BVH: one BVH per
// geometry, a top level over them) so that a scene-time update touches only what moves: set_scene_time rewrites
// the moving meshes' vertices, Embree refits their BVHs (RTC_BUILD_QUALITY_REFIT) and rebuilds the top level over
// the geometries' bounds; static meshes' BVHs are never rebuilt (docs/server.md, "Motion"). A static scene is built
// exactly as before. Geometry ID = mesh index in both: no instances.
#pragma once
#include "trace/ray_offset.hpp"
#include "trace/visibility_tracer.hpp"

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dhr::server {

struct EmbreeBuildOptions {
  // Measured on living_room.glb (docs/server.md): HIGH (spatial splits) traces faster and its extra build
  // time is small; ROBUST keeps rays from slipping through shared edges at a small cost.
  bool high_quality = true;
  bool robust = true;
  uint32_t threads = 0;  // Embree's build threads; 0 = all cores
};

// A primary hit, in the scene's relative frame (EmbreeScene::origin() is its world position).
struct SurfaceHit {
  uint32_t mesh = 0;      // index into Scene::meshes
  uint32_t triangle = 0;  // triangle index within the mesh
  float u = 0.0f;         // barycentrics: p = (1-u-v) v0 + u v1 + v v2
  float v = 0.0f;
  glm::vec3 position{0.0f};          // from the triangle's vertices and the barycentrics (not o + t d)
  glm::vec3 geometric_normal{0.0f};  // unit, on the viewer's side (flipped for back hits)
  glm::vec3 shading_normal{0.0f};    // unit interpolated vertex normal, flipped together with the above
  bool back_face = false;            // the ray hit the back of a (double-sided) triangle
};

// Per-mesh data the tracer needs after the build (the Scene itself need not outlive the tracer).
struct EmbreeMesh {
  // Relative to the origin; one padding element at the end (Embree). A moving mesh: at the scene time.
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;    // world space unit normals, one per vertex (a moving mesh: at the scene time)
  std::vector<uint32_t> indices;
  // Per run of kEmbreeChunkTriangles consecutive triangles, the box of their vertices (lo, then hi; a moving mesh:
  // the box of its box at rest moved to the scene time): what nearest_distance with planes looks through instead of
  // the BVH.
  std::vector<glm::vec3> chunk_bounds;
  glm::vec3 bounds[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};  // the chunks' box (lo, hi)
  bool double_sided = false;
};
inline constexpr size_t kEmbreeChunkTriangles = 32;

// What the last scene-time update did (EmbreeScene::set_scene_time).
struct MotionStats {
  uint32_t moving_meshes = 0;     // meshes on moving nodes (refitted when they move); 0 for a static scene
  uint64_t moving_vertices = 0;   // their vertices
  uint32_t moved_meshes = 0;      // last update: meshes whose motion changed (vertices updated, BVH refitted)
  uint64_t moved_vertices = 0;    // last update: their vertices
  double last_update_ms = 0.0;    // last update: wall time (vertices, refits, top-level rebuild)
  uint64_t updates = 0;           // set_scene_time calls so far
};

class EmbreeScene {
 public:
  // Throws std::runtime_error when Embree cannot be initialised or the build fails.
  static std::unique_ptr<EmbreeScene> create(const Scene& scene, const EmbreeBuildOptions& options = {});
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }
  // World position of the relative frame's origin (the bounding-box centre).
  const glm::dvec3& origin() const { return origin_; }
  glm::vec3 to_relative(const glm::dvec3& world) const { return glm::vec3(world - origin_); }
  // Shadow-ray origin offset for this scene's size (ray_offset.hpp).
  const RayOffset& ray_offset() const { return ray_offset_; }
  const AccelStats& stats() const { return stats_; }
  const std::vector<EmbreeMesh>& meshes() const { return meshes_; }
  // "Embree 3.13.5 (<ISA>), N threads"-style text for the device field of reports.
  std::string description(uint32_t trace_threads) const;

  // Moves the scene to scene time `t` (seconds): each moving mesh's EmbreeMesh positions and normals are moved by
  // mesh_motion_at(scene, mesh, t, overrides) from their rest positions (O(moving vertices); Embree shares the vertex buffer),
  // its geometry is committed (a BVH refit), then the scene (the top level over the geometries). Meshes whose motion
  // did not change are not touched; nothing is committed when none changed. `scene` is the Scene this was created from
  // (only its animation and its meshes' node and T_world_local are read: a copy without vertices will do).
  // A static scene only records t. Not concurrent with tracing. Throws std::runtime_error when Embree fails.
  void set_scene_time(const Scene& scene, double t, const NodeOverrides* overrides = nullptr);
  double scene_time() const { return scene_time_; }
  const MotionStats& motion_stats() const { return motion_stats_; }
  // Whether some mesh moves (the scene was built dynamic).
  bool is_dynamic() const { return !moving_.empty(); }
  // The meshes on moving nodes (mesh indices, ascending).
  std::vector<uint32_t> moving_meshes() const;

  // Surface point of Embree hit (geometry = mesh index, primitive, u, v) seen along ray direction `dir`.
  SurfaceHit surface(uint32_t mesh, uint32_t triangle, float u, float v, const glm::vec3& dir) const;

  // Single primary ray (origin relative, any direction length): the closest front face, or a face of a
  // double-sided material. std::nullopt on a miss.
  std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& dir, float tnear = 0.0f) const;
  // Shadow-style query: any surface (both sides) within (0, tfar) along dir.
  bool occluded(const glm::vec3& origin, const glm::vec3& dir, float tfar) const;
  // Whether any triangle comes within `radius` of `center` (relative frame) and, with `planes`, meets the convex
  // region where every plane's dot((x, 1)) >= 0: an Embree point query with the exact point-triangle distance,
  // then each such triangle clipped by the planes (touching counts as meeting; at most 6 planes, more throw
  // std::invalid_argument; a non-finite point or plane: true).
  bool geometry_within(const glm::vec3& center, float radius, const std::vector<glm::vec4>& planes = {}) const;
  // The distance from `center` to the nearest triangle, or `max_radius` when none is nearer; with `planes`, to the
  // nearest part of a triangle in the convex region where every plane's dot((x, 1)) >= 0 (each triangle clipped
  // by them; at most 6 planes, more throw std::invalid_argument). A non-finite point or plane: 0.
  float nearest_distance(const glm::vec3& center, float max_radius, const std::vector<glm::vec4>& planes = {}) const;

 private:
  EmbreeScene() = default;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  glm::dvec3 origin_{0.0};
  RayOffset ray_offset_;
  AccelStats stats_;
  std::vector<EmbreeMesh> meshes_;
  // A mesh on a moving node: its rest data and its Embree geometry (refitted at each update).
  struct MovingMesh {
    uint32_t mesh = 0;                      // index into meshes_ (and its geometry ID)
    RTCGeometry geometry = nullptr;         // retained until the destructor
    std::vector<glm::vec3> rest_positions;  // world space, as the Scene stores them
    std::vector<glm::vec3> rest_normals;
    std::vector<glm::vec3> rest_chunk_bounds;  // EmbreeMesh::chunk_bounds at rest, world space
    glm::dmat4 motion{1.0};                 // the motion its vertices are at (identity: at rest)
  };
  std::vector<std::unique_ptr<MovingMesh>> moving_;
  double scene_time_ = 0.0;
  MotionStats motion_stats_;
  std::atomic<int64_t> memory_bytes_{0};
  static bool on_memory(void* user, ssize_t bytes, bool post);
};

// The tracer's one ray set-up: origin, direction, (0, tfar), every mask bit, no time. Shared by the
// single-ray queries above and the tile kernel's packets and streams.
RTCRay make_rtc_ray(const glm::vec3& origin, const glm::vec3& dir, float tfar);

// Embree intersection filter: rejects hits on the back of single-sided triangles (the client's rasterizer
// culls those). Set on single-sided geometries for rtcIntersect only; shadow rays (rtcOccluded) see
// every face. Exposed for tests.
void reject_back_faces(const RTCFilterFunctionNArguments* args);

}  // namespace dhr::server
