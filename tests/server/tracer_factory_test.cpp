// Backend names and create_tracer. The test environment hides every Vulkan driver (CMakeLists.txt).
#include "trace/embree/embree_tracer.hpp"
#include "test_scenes.hpp"
#include "trace/visibility_tracer.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <limits>
#include <stdexcept>

namespace dhr::server {
namespace {

TEST(TracerFactory, ParsesAndNamesBackends) {
  for (TracerBackend b : {TracerBackend::kAuto, TracerBackend::kEmbree, TracerBackend::kVulkan})
    EXPECT_EQ(parse_tracer_backend(tracer_backend_name(b)), b);
  EXPECT_THROW(parse_tracer_backend("optix"), std::invalid_argument);
  EXPECT_THROW(parse_tracer_backend(""), std::invalid_argument);
  EXPECT_THROW(parse_tracer_backend("Embree"), std::invalid_argument);
}

Scene small_scene() {
  Scene scene = test::make_empty_scene();
  test::add_grid(scene, {-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, 1, test::kSingleSided);
  scene.lights = {test::point_light({0.0f, 1.0f, 0.0f}, 1.0f)};
  test::finalize(scene);
  return scene;
}

TEST(TracerFactory, EmbreeOnRequest) {
  auto tracer = create_tracer(TracerBackend::kEmbree, small_scene());
  ASSERT_NE(tracer, nullptr);
  EXPECT_EQ(tracer->backend(), TracerBackend::kEmbree);
  EXPECT_EQ(tracer->light_count(), 1u);
}

TEST(TracerFactory, AutoWithoutAGpuIsEmbree) {
  EXPECT_FALSE(find_ray_tracing_gpu().has_value());
  auto tracer = create_tracer(TracerBackend::kAuto, small_scene());
  EXPECT_EQ(tracer->backend(), TracerBackend::kEmbree);
}

TEST(TracerFactory, VulkanWithoutADriverFailsWithAReason) {
  try {
    create_tracer(TracerBackend::kVulkan, small_scene());
    FAIL() << "expected an error: the test environment has no Vulkan driver";
  } catch (const std::runtime_error& e) {
    EXPECT_FALSE(std::string(e.what()).empty());
  }
}

TEST(TracerFactory, TooManyLightsIsAnError) {
  Scene scene = small_scene();
  scene.lights.assign(kMaxSlotLights + 1, test::point_light({0.0f, 1.0f, 0.0f}, 1.0f));
  EXPECT_THROW(create_tracer(TracerBackend::kEmbree, scene), std::runtime_error);
  // 33 lights without a range all reach every point: 32 take a slot each, the last is left out and named.
  scene.lights.resize(kMaxLights + 1);
  const auto tracer = create_tracer(TracerBackend::kEmbree, scene);
  ASSERT_NE(tracer->light_slots(), nullptr);
  EXPECT_EQ(tracer->light_count(), kMaxLights);
  EXPECT_EQ(tracer->light_slots()->dropped(), std::vector<uint32_t>{kMaxLights});
}

TEST(TracerFactory, BadGeometryIsAnErrorNotACrash) {
  Scene scene = small_scene();
  scene.meshes[0].indices[2] = 999;
  EXPECT_THROW(create_tracer(TracerBackend::kEmbree, scene), std::runtime_error);
  scene = small_scene();
  scene.meshes[0].positions[1].y = std::numeric_limits<float>::infinity();
  EXPECT_THROW(create_tracer(TracerBackend::kEmbree, scene), std::runtime_error);
}

TEST(TracerFactory, ThreadCountsAboveTheBoundAreAnError) {
  TracerOptions options;
  options.threads = kMaxTracerThreads + 1;
  EXPECT_THROW(create_tracer(TracerBackend::kEmbree, small_scene(), options), std::invalid_argument);
  options.threads = kMaxTracerThreads;
  EXPECT_NO_THROW(create_tracer(TracerBackend::kEmbree, small_scene(), options));
}

// The system refuses new threads (a real limit: the process drops to an unprivileged user whose process count is
// above RLIMIT_NPROC). trace() must end with an error naming the thread, after joining those it started; a
// std::thread left joinable would terminate the process instead.
TEST(TracerFactory, ATracerThreadThatCannotStartIsAnErrorNotACrash) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to drop to another user whose process limit can be lowered";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int code = 10;
    try {
      TracerOptions options;
      options.threads = 8;
      auto tracer = create_tracer(TracerBackend::kEmbree, small_scene(), options);
      const Camera camera = test::look_camera({0.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, 128, 96, 60.0);
      const rlimit one{1, 1};
      if (setrlimit(RLIMIT_NPROC, &one) != 0 || setgid(65534) != 0 || setuid(65534) != 0) _exit(20);
      VisibilityBuffer out;
      TraceStats stats;
      tracer->trace(camera, out, stats);
      code = 11;  // every thread started: the limit did not bite
    } catch (const std::runtime_error& e) {
      code = std::strstr(e.what(), "cannot start tracer thread") != nullptr ? 0 : 12;
    } catch (...) {
      code = 13;
    }
    _exit(code);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  if (WEXITSTATUS(status) == 20) GTEST_SKIP() << "cannot lower RLIMIT_NPROC and drop to uid 65534 here";
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: setup threw, 11: no thread was refused, 12: another error, 13: not "
                                       "a runtime_error";
}

TEST(TracerFactory, EmptySceneTracesToBackground) {
  Scene scene = test::make_empty_scene();
  scene.lights = {test::point_light({0.0f, 1.0f, 0.0f}, 1.0f)};
  test::finalize(scene);
  auto tracer = create_tracer(TracerBackend::kEmbree, scene);
  VisibilityBuffer vis;
  TraceStats stats;
  tracer->trace(test::look_camera({0.0, 0.0, 1.0}, {0.0, 0.0, 0.0}, 8, 8), vis, stats);
  EXPECT_EQ(stats.background_pixels, 64u);
  EXPECT_EQ(stats.shadow_rays, 0u);
}

}  // namespace
}  // namespace dhr::server
