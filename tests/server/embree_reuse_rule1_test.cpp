// Rule 1 of reuse (trace/reuse/reuse_frame.hpp) at the image's sides and near the eye, against the exhaustive trace:
// geometry beside the head that no side lets in takes no block away, geometry entering across a side is never covered
// by a block, a plane beside the eye is no occluder; and the point query within planes that bounds the sides.
#include "reuse_pair.hpp"
#include "reuse_room.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "trace/reuse/reuse_frame.hpp"
#include "test_scenes.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace dhr::server {
namespace {

using namespace reuse_test;  // the room, its cameras, the bound

// The nearest part of the triangles inside a region of planes, against the floor's and the box's analytic distances
// (room: floor y = 0 over x, z in [-4, 4]; the sliding box from x in [-2, -1.6] at t = 0, 0.5 m further at 0.5 s).
TEST(ReuseRule, NearestDistanceWithinPlanesIsThatOfTheClippedTriangles) {
  EmbreeTracer tracer(room(true, false), threads(1));
  const EmbreeScene& scene = tracer.embree_scene();
  auto rel = [&](double x, double y, double z) { return scene.to_relative(glm::dvec3(x, y, z)); };
  // The plane through `at` facing `n` (the region is on n's side).
  auto plane = [&](const glm::vec3& n, double x, double y, double z) {
    return glm::vec4(n, -glm::dot(n, rel(x, y, z)));
  };
  const glm::vec3 above_floor = rel(0.0, 0.05, 2.0);
  EXPECT_NEAR(scene.nearest_distance(above_floor, 10.0f), 0.05f, 1e-5f);
  EXPECT_NEAR(scene.nearest_distance(above_floor, 10.0f, {plane({1, 0, 0}, 1.0, 0.0, 0.0)}), std::sqrt(1.0025f),
              1e-5f);
  EXPECT_NEAR(scene.nearest_distance(above_floor, 10.0f, {plane({1, 0, 0}, 1.0, 0, 0), plane({0, 0, -1}, 0, 0, 1.0)}),
              std::sqrt(2.0025f), 1e-5f);
  EXPECT_EQ(scene.nearest_distance(above_floor, 10.0f, {plane({0, 1, 0}, 0.0, 10.0, 0.0)}), 10.0f);  // nothing there
  // beyond the radius
  EXPECT_EQ(scene.nearest_distance(above_floor, 0.5f, {plane({1, 0, 0}, 1.0, 0.0, 0.0)}), 0.5f);
  // Above the floor and in front of the wall and the static box: the sliding box alone, where it is now.
  const std::vector<glm::vec4> beside{plane({0, 1, 0}, 0.0, 0.2, 0.0), plane({0, 0, 1}, 0.0, 0.0, 0.1)};
  const glm::vec3 from = rel(0.0, 0.6, 0.7);
  EXPECT_NEAR(scene.nearest_distance(from, 10.0f, beside), 1.6f, 1e-4f);
  tracer.set_scene_time(0.5);
  EXPECT_NEAR(scene.nearest_distance(from, 10.0f, beside), 1.1f, 1e-4f);
  EXPECT_THROW(scene.nearest_distance(from, 10.0f, std::vector<glm::vec4>(7, glm::vec4(0, 1, 0, 0))),
               std::invalid_argument);
  // A NaN point or plane knows nothing: as near as can be, and something within.
  const float nan = std::nanf("");
  EXPECT_EQ(scene.nearest_distance(glm::vec3(nan, 0, 0), 10.0f), 0.0f);
  EXPECT_EQ(scene.nearest_distance(from, 10.0f, {glm::vec4(nan, 1, 0, 0)}), 0.0f);
  EXPECT_TRUE(scene.geometry_within(glm::vec3(0, nan, 0), 0.01f));
}

// A small box 0.2 m to the left of an eye that drifts right, outside the frustum: geometry no pixel saw, 0.2 m from
// the eye, but in no part of the next frustum that lies beyond a side of the previous one, so it cannot enter the
// image. Blocks are taken as without it (bounding by the nearest geometry anywhere took 16 % fewer pixels here);
// the bits stay within the bound.
TEST(EmbreeReuse, NearGeometryThatCannotEnterTheImageTakesNothingAway) {
  uint64_t reused[2] = {0, 0};
  for (const bool near_box : {false, true}) {
    Scene scene = room(false, false);
    if (near_box) {
      test::add_box(scene, glm::vec3(0.0f, 1.55f, 2.95f), glm::vec3(0.1f, 1.65f, 3.05f), test::kSingleSided);
      test::finalize(scene);
    }
    EmbreeTracer tracer(scene, threads(2));
    std::array<ReuseFrame, 2> frames;
    uint64_t bits = 0, differing = 0;
    for (int i = 0; i < 6; ++i) {
      const Camera camera = camera_at(0.3 + 0.006 * i, 1.6, 3.0);
      ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2]);
      bits += (p.exact_stats.pixels - p.exact_stats.background_pixels) * tracer.light_count();
      differing += differing_bits(p.exact, p.reused);
      reused[near_box] += p.reused_stats.reused_pixels;
    }
    EXPECT_LE(static_cast<double>(differing), kMaxDifferingShare * static_cast<double>(bits));
  }
  EXPECT_GT(reused[0], 0u);
  EXPECT_GT(reused[1], reused[0] * 9 / 10) << "without the box " << reused[0] << ", with it " << reused[1];
}

// A 2 cm pole, 20 cm tall, 0.5 m ahead, just beyond the right side of the frustum, and an eye drifting right 3 cm a
// frame: the pole enters the image across that side, 14 pixels a frame. Rule 1 alone (no pairs) still gives the
// exhaustive trace's bits in every frame (without the margin for what lies beyond that side, frame 1 differs).
TEST(EmbreeReuse, GeometryEnteringAcrossASideIsNotCoveredByBlocks) {
  const Camera first = camera_at(0.3, 1.6, 3.0);
  const glm::dmat3 R = glm::mat3_cast(first.T_world_eye.orientation);
  const glm::dvec3 centre = first.T_world_eye.position + R * glm::dvec3(first.tangents.right * 0.5 + 0.05, 0.0, -0.5);
  Scene scene = room(false, false);
  const uint32_t pole = static_cast<uint32_t>(scene.meshes.size());
  test::add_box(scene, glm::vec3(centre - glm::dvec3(0.01, 0.1, 0.01)), glm::vec3(centre + glm::dvec3(0.01, 0.1, 0.01)),
                test::kSingleSided);
  test::finalize(scene);
  EmbreeTracer tracer(scene, threads(2));
  const EmbreeScene& embree = tracer.embree_scene();
  auto pole_pixels = [&](const Camera& camera) {  // pixels whose primary ray meets the pole first
    uint32_t n = 0;
    for (uint32_t y = 0; y < camera.extent.height; ++y)
      for (uint32_t x = 0; x < camera.extent.width; ++x) {
        const auto hit = embree.intersect(embree.to_relative(camera.T_world_eye.position),
                                          glm::vec3(camera.world_ray(x + 0.5, y + 0.5)));
        n += hit && hit->mesh >= pole ? 1u : 0u;
      }
    return n;
  };
  ReuseOptions options;
  options.pairs = false;
  std::array<ReuseFrame, 2> frames;
  uint64_t reused = 0;
  Camera camera = first;
  for (int i = 0; i < 8; ++i) {
    camera = camera_at(0.3 + 0.03 * i, 1.6, 3.0);
    ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2], options);
    EXPECT_EQ(differing_bits(p.exact, p.reused), 0u) << "frame " << i;
    reused += p.reused_stats.reused_pixels;
  }
  EXPECT_EQ(pole_pixels(first), 0u);
  EXPECT_GT(pole_pixels(camera), 100u);  // in the image by the last frame
  EXPECT_GT(reused, 0u);
}

// The eye 5 cm from the back wall, looking along it and drifting along it 1 cm a frame: the wall fills the image's
// left side at depths down to centimetres, but a plane cannot slide over itself, so it does not narrow what is taken
// beside it: 52 % of the hit pixels taken whole (25 % while every surface pixel counted as a possible occluder);
// the bits stay within the bound.
TEST(EmbreeReuse, APlaneBesideTheEyeDoesNotNarrowTheBlocks) {
  EmbreeTracer tracer(room(false, false), threads(2));
  std::array<ReuseFrame, 2> frames;
  uint64_t bits = 0, differing = 0, reused = 0, hits = 0;
  for (int i = 0; i < 6; ++i) {
    const glm::dvec3 eye(-2.0 + 0.01 * i, 1.5, -3.95);
    const Camera camera = test::look_camera(eye, eye + glm::dvec3(1.0, -0.3, 0.25), 256, 160, 80.0);
    ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2]);
    bits += (p.exact_stats.pixels - p.exact_stats.background_pixels) * tracer.light_count();
    differing += differing_bits(p.exact, p.reused);
    if (i > 0) {
      reused += p.reused_stats.reused_pixels;
      hits += p.exact_stats.pixels - p.exact_stats.background_pixels;
    }
  }
  EXPECT_LE(static_cast<double>(differing), kMaxDifferingShare * static_cast<double>(bits));
  EXPECT_GT(reused, hits * 2 / 5) << reused << " of " << hits;
}

// An eye walking up to the back wall: each frame's traced points land more than a pixel apart (up to 1.1), so the
// traced pixel nearest a block's centre can lie more than half a pixel from it. The search takes it (within 0.75,
// half the widest spacing a block accepts): the blocks are taken and the bits stay exact (rule 1 alone): 92 % of
// the hits taken whole, where stopping within half a pixel took 81 %.
TEST(EmbreeReuse, AnEyeComingCloserFindsItsBlocks) {
  EmbreeTracer tracer(room(false, false), threads(2));
  ReuseOptions options;
  options.pairs = false;
  options.refresh = false;
  std::array<ReuseFrame, 2> frames;
  uint64_t bits = 0, differing = 0, reused = 0, hits = 0;
  for (int i = 0; i < 6; ++i) {
    const glm::dvec3 eye(0.2, 1.6, -2.4 - 0.12 * i);
    const Camera camera = test::look_camera(eye, glm::dvec3(0.5, 1.0, -4.0), 256, 160, 70.0);
    ReusePair p = trace_both(tracer, camera, i ? &frames[(i + 1) % 2] : nullptr, frames[i % 2], options);
    bits += (p.exact_stats.pixels - p.exact_stats.background_pixels) * tracer.light_count();
    differing += differing_bits(p.exact, p.reused);
    if (i > 0) {
      reused += p.reused_stats.reused_pixels;
      hits += p.exact_stats.pixels - p.exact_stats.background_pixels;
    }
  }
  EXPECT_EQ(differing, 0u) << "of " << bits;
  EXPECT_GT(reused, hits * 87 / 100) << reused << " of " << hits;
}

// The nearby-depth levels against their definition: per level, the minimum cell depth over the 3x3 neighbourhood of
// cells of kNearRadius[k] pixels around each one, computed here cell by cell (finish_reuse_distances pools coarser
// levels from finer ones). An odd grid, so the last cells of each level are partial.
TEST(ReuseRule, NearbyDepthLevelsAreTheirNeighbourhoodsMinimum) {
  ReuseFrame frame;
  frame.cells_x = 157;
  frame.cells_y = 93;
  const size_t cells = static_cast<size_t>(frame.cells_x) * frame.cells_y;
  frame.cell_depth.resize(cells);
  frame.cell_surface_depth.assign(cells, 3.0f);
  frame.edge_distance.assign(cells, 255);
  uint32_t state = 12345u;
  for (float& d : frame.cell_depth) {
    state = state * 1664525u + 1013904223u;
    d = (state >> 8) % 7 == 0 ? 0.05f + static_cast<float>(state >> 20) * 1e-3f : 1e30f;  // sparse occluders
  }
  finish_reuse_distances(frame);
  for (uint32_t k = 0; k < kNearLevels; ++k) {
    const uint32_t per = kNearRadius[k] / kReuseCell;
    const uint32_t nx = (frame.cells_x + per - 1) / per, ny = (frame.cells_y + per - 1) / per;
    ASSERT_EQ(frame.near_x[k], nx) << k;
    ASSERT_EQ(frame.near[k].size(), static_cast<size_t>(nx) * ny) << k;
    for (uint32_t py = 0; py < ny; ++py)
      for (uint32_t px = 0; px < nx; ++px) {
        float want = std::numeric_limits<float>::max();
        for (uint32_t y = 0; y < frame.cells_y; ++y)
          for (uint32_t x = 0; x < frame.cells_x; ++x)
            if (x / per + 1 >= px && x / per <= px + 1 && y / per + 1 >= py && y / per <= py + 1)
              want = std::min(want, frame.cell_depth[static_cast<size_t>(y) * frame.cells_x + x]);
        ASSERT_EQ(frame.near[k][static_cast<size_t>(py) * nx + px], want) << "level " << k << " at " << px << "," << py;
      }
  }
}

}  // namespace
}  // namespace dhr::server
