// Shared by the Vulkan tracer tests (vulkan_tracer_test.cpp, vulkan_tracer_real_scene_test.cpp): the
// fixture (validation on, zero errors) and the comparison with the Embree reference. Two backends agree when
// fewer than 0.1% of the pixel-light bits differ and every differing bit lies within a pixel of a silhouette
// or a shadow boundary.
#pragma once
#include "scene/camera_bookmarks.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"
#include "trace/vulkan/vulkan_tracer.hpp"

#include "vk/context.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace dhr::server::tracer_test {

// Validation on for every tracer; the process-wide count also catches errors while a context is destroyed.
class VulkanTracerTest : public ::testing::Test {
 protected:
  void SetUp() override { errors_before_ = vk::process_validation_error_count(); }
  void TearDown() override {
    EXPECT_EQ(vk::process_validation_error_count() - errors_before_, 0u) << "Vulkan validation errors (see log)";
  }
  static TracerOptions vk_options(SkipOptions skip = {}) {
    TracerOptions o;
    o.skip = skip;
    o.vk_validation = true;
    return o;
  }
  static TracerOptions embree_options() {
    TracerOptions o;
    o.threads = 2;
    return o;
  }
  uint32_t errors_before_ = 0;
};

using test::bookmark_cameras;  // tests/server/test_scenes.hpp
using test::load_scene_or_fail;

// Per pixel of `camera` (row-major): 1 within a pixel (3x3) of a silhouette of the reference's primary hits (hit
// and miss, another mesh, or a depth jump above 2 % between 4-neighbours), where the backends may see different
// surfaces.
std::vector<uint8_t> near_silhouette(const EmbreeTracer& embree, const Camera& camera);

// For an agreement failure: where the reference's shadow ray from pixel (x, y) to each point or spot light in `bits`
// first meets a front face, and how close to that triangle's edges (its smallest barycentric); text starting "; ".
std::string describe_shadow_rays(const EmbreeTracer& embree, const Camera& camera, const std::vector<SceneLight>& lights,
                                 int x, int y, uint32_t bits);

// Whether the reference's shadow ray from pixel (x, y) to a point or spot light meets a surface within 0.01 % of the
// light's distance: a light on a surface, where either tracer's answer stands (both end the ray at the same
// distance; which triangle that close counts is each implementation's arithmetic). expect_agreement explains such
// differing bits.
bool occluder_at_the_light(const EmbreeScene& scene, const Camera& camera, const SceneLight& light, int x, int y);

// Traces every camera with both backends; expects < 0.1% differing bits and none unexplained (lights on a surface
// explained). With scene_times, both tracers are moved to each time in turn (set_scene_time) and every camera is
// traced at each.
void expect_agreement(const Scene& scene, const std::vector<Camera>& cameras, const TracerOptions& vk_options,
                      const TracerOptions& embree_options, const VulkanTracerConfig& config = {},
                      const std::vector<double>& scene_times = {});

}  // namespace dhr::server::tracer_test
