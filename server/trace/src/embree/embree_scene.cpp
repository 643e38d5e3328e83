#include "trace/embree/embree_scene.hpp"

#include "log/log.hpp"
#include "scene/scene_at.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

namespace dhr::server {
namespace {

// EmbreeMesh::chunk_bounds and bounds from its positions and indices.
void update_chunk_bounds(EmbreeMesh& mesh) {
  const size_t triangles = mesh.indices.size() / 3;
  const size_t chunks = (triangles + kEmbreeChunkTriangles - 1) / kEmbreeChunkTriangles;
  mesh.chunk_bounds.resize(2 * chunks);
  for (size_t c = 0; c < chunks; ++c) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    const size_t end = std::min(triangles, (c + 1) * kEmbreeChunkTriangles) * 3;
    for (size_t i = c * kEmbreeChunkTriangles * 3; i < end; ++i) {
      lo = glm::min(lo, mesh.positions[mesh.indices[i]]);
      hi = glm::max(hi, mesh.positions[mesh.indices[i]]);
    }
    mesh.chunk_bounds[2 * c] = lo;
    mesh.chunk_bounds[2 * c + 1] = hi;
    mesh.bounds[0] = c == 0 ? lo : glm::min(mesh.bounds[0], lo);
    mesh.bounds[1] = c == 0 ? hi : glm::max(mesh.bounds[1], hi);
  }
}

// A moving mesh's boxes at `motion` from its boxes at rest (`rest`, world space, as chunk_bounds): each the box of
// the moved corners (it holds the moved triangles; cheaper than the vertices again), relative to `origin`.
void move_chunk_bounds(EmbreeMesh& mesh, const std::vector<glm::vec3>& rest, const glm::dmat4& motion,
                       const glm::dvec3& origin) {
  mesh.chunk_bounds.resize(rest.size());
  for (size_t c = 0; 2 * c < rest.size(); ++c) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (uint32_t k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1u) ? rest[2 * c + 1].x : rest[2 * c].x, (k & 2u) ? rest[2 * c + 1].y : rest[2 * c].y,
                             (k & 4u) ? rest[2 * c + 1].z : rest[2 * c].z);
      const glm::vec3 moved(glm::dvec3(moved_position(motion, corner)) - origin);
      lo = glm::min(lo, moved);
      hi = glm::max(hi, moved);
    }
    mesh.chunk_bounds[2 * c] = lo;
    mesh.chunk_bounds[2 * c + 1] = hi;
    mesh.bounds[0] = c == 0 ? lo : glm::min(mesh.bounds[0], lo);
    mesh.bounds[1] = c == 0 ? hi : glm::max(mesh.bounds[1], hi);
  }
}

void on_embree_error(void* /*user*/, RTCError code, const char* message) {
  log::error("embree: error %d: %s", static_cast<int>(code), message ? message : "");
}

std::string device_error_text(RTCDevice device) {
  switch (rtcGetDeviceError(device)) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

glm::vec3 face_normal(const EmbreeMesh& mesh, uint32_t triangle) {
  const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(triangle)];
  const glm::vec3& a = mesh.positions[idx[0]];
  return glm::cross(mesh.positions[idx[1]] - a, mesh.positions[idx[2]] - a);  // CCW front (glTF)
}

}  // namespace

void reject_back_faces(const RTCFilterFunctionNArguments* args) {
  const auto* mesh = static_cast<const EmbreeMesh*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const glm::vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                        RTCRayN_dir_z(args->ray, args->N, i));
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    // Edge-on (dot == 0) counts as back-facing: a rasterizer produces no fragments for it either.
    if (!(glm::dot(face_normal(*mesh, prim), dir) < 0.0f)) args->valid[i] = 0;
  }
}

bool EmbreeScene::on_memory(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<EmbreeScene*>(user)->memory_bytes_.fetch_add(static_cast<int64_t>(bytes));
  return true;
}

std::unique_ptr<EmbreeScene> EmbreeScene::create(const Scene& scene, const EmbreeBuildOptions& options) {
  std::unique_ptr<EmbreeScene> es(new EmbreeScene());
  const uint32_t threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  // set_affinity=0: the server shares the machine with the client in the eval; no thread pinning.
  const std::string config = "threads=" + std::to_string(threads) + ",set_affinity=0";
  es->device_ = rtcNewDevice(config.c_str());
  if (!es->device_) throw std::runtime_error("embree: cannot create a device: " + device_error_text(nullptr));
  rtcSetDeviceErrorFunction(es->device_, on_embree_error, nullptr);
  rtcSetDeviceMemoryMonitorFunction(es->device_, &EmbreeScene::on_memory, es.get());

  const auto t0 = std::chrono::steady_clock::now();
  es->origin_ = scene.bounds.empty() ? glm::dvec3(0.0) : glm::dvec3(scene.bounds.min) * 0.5 +
                                                              glm::dvec3(scene.bounds.max) * 0.5;
  es->ray_offset_ = scaled_ray_offset(ray_offset_scale(scene.bounds));
  // Meshes with triangles on moving nodes make the scene dynamic; otherwise it is built as it always was.
  const auto moves = [&](const SceneMesh& m) {
    return m.indices.size() >= 3 && !m.positions.empty() && scene.animation.find(m.node) != nullptr;
  };
  const bool dynamic = !scene.animation.empty() && std::any_of(scene.meshes.begin(), scene.meshes.end(), moves);
  es->scene_ = rtcNewScene(es->device_);
  // A dynamic scene: DYNAMIC with LOW scene quality selects Embree's two-level BVH (one BVH per geometry, each at
  // its own quality below, and a top level over them); a commit rebuilds only the committed geometries' BVHs and
  // the top level. (With MEDIUM or HIGH scene quality Embree 3 rebuilds the whole scene at every commit: measured,
  // an update then costs as much as a full build; docs/server.md, "Motion".)
  rtcSetSceneBuildQuality(es->scene_, dynamic ? RTC_BUILD_QUALITY_LOW
                                              : (options.high_quality ? RTC_BUILD_QUALITY_HIGH
                                                                      : RTC_BUILD_QUALITY_MEDIUM));
  rtcSetSceneFlags(es->scene_, static_cast<RTCSceneFlags>((options.robust ? RTC_SCENE_FLAG_ROBUST : 0) |
                                                          (dynamic ? RTC_SCENE_FLAG_DYNAMIC : 0)));

  es->meshes_.resize(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& src = scene.meshes[m];
    EmbreeMesh& dst = es->meshes_[m];
    const size_t tri_count = src.indices.size() / 3;
    if (tri_count == 0 || src.positions.empty()) continue;
    // The loader validates files; scenes built in code get the same guarantee here (Embree does not check).
    for (size_t i = 0; i < tri_count * 3; ++i) {
      if (src.indices[i] >= src.positions.size())
        throw std::runtime_error("embree: mesh '" + src.name + "': index " + std::to_string(src.indices[i]) +
                                 " out of range (" + std::to_string(src.positions.size()) + " vertices)");
    }
    for (const glm::vec3& p : src.positions) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw std::runtime_error("embree: mesh '" + src.name + "': non-finite vertex position");
    }
    dst.double_sided = src.material < scene.materials.size() && scene.materials[src.material].double_sided;
    // Subtract the origin in double: the float result keeps full precision near the scene.
    dst.positions.reserve(src.positions.size() + 1);
    for (const glm::vec3& p : src.positions) dst.positions.push_back(glm::vec3(glm::dvec3(p) - es->origin_));
    dst.positions.emplace_back(0.0f);  // Embree reads vertex buffers with 16-byte loads: pad the last one
    dst.normals = src.normals;
    if (dst.normals.size() != src.positions.size()) dst.normals.assign(src.positions.size(), glm::vec3(0.0f));
    dst.indices.assign(src.indices.begin(), src.indices.begin() + static_cast<std::ptrdiff_t>(tri_count * 3));
    update_chunk_bounds(dst);

    RTCGeometry geom = rtcNewGeometry(es->device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, dst.positions.data(), 0,
                               sizeof(glm::vec3), src.positions.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, dst.indices.data(), 0,
                               3 * sizeof(uint32_t), tri_count);
    rtcSetGeometryUserData(geom, &dst);
    if (!dst.double_sided) rtcSetGeometryIntersectFilterFunction(geom, reject_back_faces);
    const bool moving = dynamic && moves(src);
    if (dynamic) {
      // Static geometries are built once, moving ones refitted at each update (their topology never changes).
      rtcSetGeometryBuildQuality(geom, moving ? RTC_BUILD_QUALITY_REFIT
                                              : (options.high_quality ? RTC_BUILD_QUALITY_HIGH
                                                                      : RTC_BUILD_QUALITY_MEDIUM));
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(es->scene_, geom, static_cast<unsigned>(m));
    if (moving) {
      auto mm = std::make_unique<MovingMesh>();
      mm->mesh = static_cast<uint32_t>(m);
      mm->geometry = geom;  // keeps the reference rtcNewGeometry gave (released in the destructor)
      mm->rest_positions = src.positions;
      EmbreeMesh rest;  // the boxes at rest, in world space (move_chunk_bounds)
      rest.positions = src.positions;
      rest.indices = dst.indices;
      update_chunk_bounds(rest);
      mm->rest_chunk_bounds = std::move(rest.chunk_bounds);
      mm->rest_normals = dst.normals;
      es->motion_stats_.moving_vertices += src.positions.size();
      es->moving_.push_back(std::move(mm));
    } else {
      rtcReleaseGeometry(geom);
    }
    es->stats_.triangles += tri_count;
    ++es->stats_.blas_count;
  }
  es->motion_stats_.moving_meshes = static_cast<uint32_t>(es->moving_.size());
  rtcCommitScene(es->scene_);
  if (rtcGetDeviceError(es->device_) != RTC_ERROR_NONE)
    throw std::runtime_error("embree: scene build failed: " + device_error_text(es->device_));
  es->stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  es->stats_.bytes = static_cast<uint64_t>(std::max<int64_t>(0, es->memory_bytes_.load()));
  es->stats_.instance_count = 0;  // one scene of triangle geometries: no instances
  return es;
}

EmbreeScene::~EmbreeScene() {
  for (const auto& mm : moving_) rtcReleaseGeometry(mm->geometry);
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

namespace {

// Squared distance from p to segment [a, b].
float segment_distance2(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 ab = b - a;
  const float len2 = glm::dot(ab, ab);
  const float t = len2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
  const glm::vec3 d = a + ab * t - p;
  return glm::dot(d, d);
}

// Squared distance from p to triangle (a, b, c): to its plane where p projects inside it, else to its nearest edge.
float triangle_distance2(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float n2 = glm::dot(n, n);
  if (n2 > 0.0f) {
    const float along = glm::dot(p - a, n);
    const glm::vec3 q = p - n * (along / n2);  // p on the plane
    const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.0f && glm::dot(glm::cross(c - b, q - b), n) >= 0.0f &&
                        glm::dot(glm::cross(a - c, q - c), n) >= 0.0f;
    if (inside) return along * along / n2;
  }
  return std::min({segment_distance2(p, a, b), segment_distance2(p, b, c), segment_distance2(p, c, a)});
}

// Triangle (a, b, c) clipped by the convex region where every plane's dot((x, 1)) >= 0 (Sutherland-Hodgman): the
// polygon's vertices in `out` (each plane adds at most one), their count returned (0: nothing of it there; a
// triangle touching the region keeps a point).
constexpr size_t kMaxClipPlanes = 6;
using ClippedPolygon = std::array<glm::vec3, 3 + kMaxClipPlanes>;
size_t clip_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const std::vector<glm::vec4>& planes,
                     ClippedPolygon& out) {
  ClippedPolygon next;
  out[0] = a;
  out[1] = b;
  out[2] = c;
  size_t n = 3;
  for (const glm::vec4& plane : planes) {
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3& p = out[i];
      const glm::vec3& q = out[(i + 1) % n];
      const float dp = glm::dot(glm::vec3(plane), p) + plane.w, dq = glm::dot(glm::vec3(plane), q) + plane.w;
      if (dp >= 0.0f) next[m++] = p;
      if ((dp >= 0.0f) != (dq >= 0.0f)) next[m++] = p + (q - p) * (dp / (dp - dq));
    }
    n = m;
    std::copy_n(next.begin(), n, out.begin());
    if (n == 0) return 0;
  }
  return n;
}

// One point query over `scene`: `visit` is called with the query and each candidate triangle's vertices (it may
// shrink query.radius and returns whether it did).
struct PointVisit {
  const std::vector<EmbreeMesh>* meshes = nullptr;
  std::function<bool(RTCPointQuery&, const glm::vec3&, const glm::vec3&, const glm::vec3&)> visit;
};

bool point_visit_callback(RTCPointQueryFunctionArguments* args) {
  const auto* v = static_cast<const PointVisit*>(args->userPtr);
  const EmbreeMesh& mesh = (*v->meshes)[args->geomID];
  const uint32_t* tri = &mesh.indices[static_cast<size_t>(args->primID) * 3];
  return v->visit(*args->query, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
}

float run_point_query(RTCScene scene, const glm::vec3& center, float radius, const PointVisit& visit) {
  RTCPointQuery query;
  query.x = center.x;
  query.y = center.y;
  query.z = center.z;
  query.time = 0.0f;
  query.radius = radius;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene, &query, &context, point_visit_callback, const_cast<PointVisit*>(&visit));
  return query.radius;
}

}  // namespace

namespace {

// Whether a query's point and planes are finite numbers (a NaN would make every comparison false: "nothing near").
bool finite_query(const glm::vec3& center, const std::vector<glm::vec4>& planes) {
  bool finite = std::isfinite(center.x) && std::isfinite(center.y) && std::isfinite(center.z);
  for (const glm::vec4& p : planes)
    finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
  return finite;
}

}  // namespace

float EmbreeScene::nearest_distance(const glm::vec3& center, float max_radius,
                                    const std::vector<glm::vec4>& planes) const {
  if (planes.size() > kMaxClipPlanes) throw std::invalid_argument("nearest_distance: more than 6 planes");
  if (!finite_query(center, planes)) return 0.0f;  // unknown: as near as can be
  if (planes.empty()) {
    const PointVisit visit{&meshes_, [&](RTCPointQuery& q, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
                             const float d = std::sqrt(triangle_distance2(center, a, b, c));
                             if (!(d < q.radius)) return false;
                             q.radius = d;  // shrinks the search to what is nearer
                             return true;
                           }};
    return run_point_query(scene_, center, max_radius, visit);
  }
  // Embree's query cannot skip what lies outside the planes (it would visit every triangle within the radius
  // there): the chunks' boxes instead, nearest first, each box's distance a bound on its triangles'.
  struct Candidate {
    float distance2;
    uint32_t mesh;
    uint32_t chunk;
  };
  // A box that may hold part of the region within the radius: its squared distance, else -1.
  auto box_distance2 = [&](const glm::vec3& lo, const glm::vec3& hi) {
    for (const glm::vec4& plane : planes) {  // wholly outside a plane: even its corner furthest along the normal
      const glm::vec3 corner(plane.x >= 0.0f ? hi.x : lo.x, plane.y >= 0.0f ? hi.y : lo.y,
                             plane.z >= 0.0f ? hi.z : lo.z);
      if (glm::dot(glm::vec3(plane), corner) + plane.w < 0.0f) return -1.0f;
    }
    const glm::vec3 d = glm::max(glm::max(lo - center, center - hi), glm::vec3(0.0f));
    const float d2 = glm::dot(d, d);
    return d2 < max_radius * max_radius ? d2 : -1.0f;
  };
  std::vector<Candidate> candidates;
  for (uint32_t m = 0; m < meshes_.size(); ++m) {
    const std::vector<glm::vec3>& bounds = meshes_[m].chunk_bounds;
    if (bounds.empty() || box_distance2(meshes_[m].bounds[0], meshes_[m].bounds[1]) < 0.0f) continue;
    for (uint32_t c = 0; 2 * c < bounds.size(); ++c) {
      const float d2 = box_distance2(bounds[2 * c], bounds[2 * c + 1]);
      if (d2 >= 0.0f) candidates.push_back({d2, m, c});
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.distance2 < b.distance2; });
  float best2 = max_radius * max_radius;
  for (const Candidate& cand : candidates) {
    if (!(cand.distance2 < best2)) break;
    const EmbreeMesh& mesh = meshes_[cand.mesh];
    const size_t end = std::min(mesh.indices.size(), (cand.chunk + 1) * kEmbreeChunkTriangles * 3);
    for (size_t i = cand.chunk * kEmbreeChunkTriangles * 3; i < end; i += 3) {
      const glm::vec3& a = mesh.positions[mesh.indices[i]];
      const glm::vec3& b = mesh.positions[mesh.indices[i + 1]];
      const glm::vec3& c = mesh.positions[mesh.indices[i + 2]];
      if (!(triangle_distance2(center, a, b, c) < best2)) continue;  // the clipped part is no nearer
      ClippedPolygon poly;
      const size_t n = clip_triangle(a, b, c, planes, poly);
      // A fan over the polygon, and its outline (a degenerate polygon has no fan).
      for (size_t k = 1; k + 1 < n; ++k)
        best2 = std::min(best2, triangle_distance2(center, poly[0], poly[k], poly[k + 1]));
      for (size_t k = 0; k < n; ++k) best2 = std::min(best2, segment_distance2(center, poly[k], poly[(k + 1) % n]));
    }
  }
  return std::sqrt(best2);
}

bool EmbreeScene::geometry_within(const glm::vec3& center, float radius, const std::vector<glm::vec4>& planes) const {
  if (planes.size() > kMaxClipPlanes) throw std::invalid_argument("geometry_within: more than 6 planes");
  if (!finite_query(center, planes)) return true;  // unknown: something may be there
  bool found = false;
  const PointVisit visit{&meshes_, [&](RTCPointQuery& q, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
                           ClippedPolygon poly;
                           if (!(triangle_distance2(center, a, b, c) <= q.radius * q.radius) ||
                               clip_triangle(a, b, c, planes, poly) == 0)
                             return false;
                           found = true;
                           q.radius = 0.0f;  // found: nothing more to look for
                           return true;
                         }};
  run_point_query(scene_, center, radius, visit);
  return found;
}

std::vector<uint32_t> EmbreeScene::moving_meshes() const {
  std::vector<uint32_t> out;
  for (const auto& mm : moving_) out.push_back(mm->mesh);
  std::sort(out.begin(), out.end());
  return out;
}

void EmbreeScene::set_scene_time(const Scene& scene, double t, const NodeOverrides* overrides) {
  const auto t0 = std::chrono::steady_clock::now();
  if (scene.meshes.size() != meshes_.size())
    throw std::runtime_error("embree: set_scene_time with another scene (" + std::to_string(scene.meshes.size()) +
                             " meshes, built with " + std::to_string(meshes_.size()) + ")");
  scene_time_ = t;
  uint32_t moved = 0;
  uint64_t moved_vertices = 0;
  for (const auto& mm : moving_) {
    const glm::dmat4 motion = mesh_motion_at(scene, scene.meshes[mm->mesh], t, overrides);
    if (motion == mm->motion) continue;
    mm->motion = motion;
    // The vertices at t: the world position as scene_at computes it, then made relative as create does (the same
    // floats as a scene built from scene_at(scene, t), up to that scene's own origin). Embree reads the same
    // buffer (shared): it refits this geometry's BVH at the commit below.
    EmbreeMesh& dst = meshes_[mm->mesh];
    const glm::dmat3 nm = normal_matrix(motion);
    for (size_t i = 0; i < mm->rest_positions.size(); ++i) {
      dst.positions[i] = glm::vec3(glm::dvec3(moved_position(motion, mm->rest_positions[i])) - origin_);
      dst.normals[i] = moved_normal(nm, mm->rest_normals[i]);
    }
    move_chunk_bounds(dst, mm->rest_chunk_bounds, motion, origin_);
    rtcUpdateGeometryBuffer(mm->geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(mm->geometry);
    ++moved;
    moved_vertices += mm->rest_positions.size();
  }
  if (moved > 0) rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
    throw std::runtime_error("embree: scene update failed: " + device_error_text(device_));
  motion_stats_.moved_meshes = moved;
  motion_stats_.moved_vertices = moved_vertices;
  motion_stats_.last_update_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ++motion_stats_.updates;
}

std::string EmbreeScene::description(uint32_t trace_threads) const {
  return std::string("Embree ") + RTC_VERSION_STRING + " (CPU), " + std::to_string(trace_threads) +
         (trace_threads == 1 ? " thread" : " threads");
}

SurfaceHit EmbreeScene::surface(uint32_t mesh, uint32_t triangle, float u, float v, const glm::vec3& dir) const {
  const EmbreeMesh& m = meshes_[mesh];
  const uint32_t* idx = &m.indices[3 * static_cast<size_t>(triangle)];
  const float w = 1.0f - u - v;
  SurfaceHit hit;
  hit.mesh = mesh;
  hit.triangle = triangle;
  hit.u = u;
  hit.v = v;
  const glm::vec3& p0 = m.positions[idx[0]];
  const glm::vec3& p1 = m.positions[idx[1]];
  const glm::vec3& p2 = m.positions[idx[2]];
  hit.position = w * p0 + u * p1 + v * p2;
  glm::vec3 ng = glm::cross(p1 - p0, p2 - p0);
  const float ng_len = glm::length(ng);
  ng = ng_len > 0.0f ? ng / ng_len : -glm::normalize(dir);
  glm::vec3 ns = w * m.normals[idx[0]] + u * m.normals[idx[1]] + v * m.normals[idx[2]];
  const float ns_len = glm::length(ns);
  ns = ns_len > 1e-6f && std::isfinite(ns_len) ? ns / ns_len : ng;
  // Double-sided back hits: the rasterizer's gl_FrontFacing flip, applied to both normals.
  if (glm::dot(ng, dir) > 0.0f) {
    hit.back_face = true;
    ng = -ng;
    ns = -ns;
  }
  hit.geometric_normal = ng;
  hit.shading_normal = ns;
  return hit;
}

RTCRay make_rtc_ray(const glm::vec3& origin, const glm::vec3& dir, float tfar) {
  RTCRay ray{};
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = 0xFFFFFFFFu;
  return ray;
}

std::optional<SurfaceHit> EmbreeScene::intersect(const glm::vec3& origin, const glm::vec3& dir, float tnear) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray = make_rtc_ray(origin, dir, std::numeric_limits<float>::infinity());
  rh.ray.tnear = tnear;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return surface(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, dir);
}

bool EmbreeScene::occluded(const glm::vec3& origin, const glm::vec3& dir, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = make_rtc_ray(origin, dir, tfar);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace dhr::server
