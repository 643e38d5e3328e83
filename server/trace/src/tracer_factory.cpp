// Backend names, GPU probing for kAuto, and create_tracer.
#include "trace/embree/embree_tracer.hpp"
#include "trace/visibility_tracer.hpp"

#include "log/log.hpp"
#include "vk/context.hpp"

#include <stdexcept>

// ---- Vulkan backend hook -------------------------------------------------------------------------------
// server/CMakeLists.txt defines DHR_HAVE_VULKAN_TRACER when server/trace/src/vulkan/vulkan_tracer.cpp exists; that file
// implements, as declared in server/trace/include/trace/vulkan/vulkan_tracer.hpp:
//   std::unique_ptr<VisibilityTracer> create_vulkan_tracer(const Scene& scene, const TracerOptions& options);
#if defined(DHR_HAVE_VULKAN_TRACER)
#include "trace/vulkan/vulkan_tracer.hpp"
#endif

namespace dhr::server {
namespace {

std::unique_ptr<VisibilityTracer> make_vulkan_tracer([[maybe_unused]] const Scene& scene,
                                                     [[maybe_unused]] const TracerOptions& options) {
#if defined(DHR_HAVE_VULKAN_TRACER)
  return create_vulkan_tracer(scene, options);
#else
  throw std::runtime_error("vulkan backend not built yet (use --backend embree)");
#endif
}

constexpr bool kVulkanTracerBuilt =
#if defined(DHR_HAVE_VULKAN_TRACER)
    true;
#else
    false;
#endif

}  // namespace

TracerBackend parse_tracer_backend(const std::string& text) {
  if (text == "auto") return TracerBackend::kAuto;
  if (text == "embree") return TracerBackend::kEmbree;
  if (text == "vulkan") return TracerBackend::kVulkan;
  throw std::invalid_argument("unknown tracer backend '" + text + "' (expected auto, embree or vulkan)");
}

const char* tracer_backend_name(TracerBackend backend) {
  switch (backend) {
    case TracerBackend::kAuto: return "auto";
    case TracerBackend::kEmbree: return "embree";
    case TracerBackend::kVulkan: return "vulkan";
  }
  return "unknown";
}

std::optional<std::string> find_ray_tracing_gpu() {
  try {
    vk::ContextOptions options;
    options.app_name = "dhr-server-probe";
    options.device = vk::DevicePreference::kGpu;  // DHR_VK_DEVICE may still override it
    options.require_ray_tracing = true;
    options.validation = false;
    auto context = vk::Context::create(options);
    if (context->info().is_cpu || !context->info().ray_tracing.enabled()) return std::nullopt;
    return context->info().name;
  } catch (const std::exception& e) {
    log::debug("tracer: no GPU with Vulkan ray tracing (%s)", e.what());
    return std::nullopt;
  }
}

std::unique_ptr<VisibilityTracer> create_tracer(TracerBackend backend, const Scene& scene,
                                                const TracerOptions& options) {
  switch (backend) {
    case TracerBackend::kEmbree: return create_embree_tracer(scene, options);
    case TracerBackend::kVulkan: return make_vulkan_tracer(scene, options);
    case TracerBackend::kAuto: break;
  }
  // kAuto: a GPU's ray-tracing pipeline beats any CPU; lavapipe does not (20-150x slower than Embree on
  // the same CPU), so a CPU-only machine gets Embree.
  if (auto gpu = find_ray_tracing_gpu()) {
    if (kVulkanTracerBuilt) {
      log::info("tracer: auto -> vulkan on %s", gpu->c_str());
      return make_vulkan_tracer(scene, options);
    }
    log::info("tracer: %s has ray tracing but the vulkan backend is not built; auto -> embree", gpu->c_str());
  }
  return create_embree_tracer(scene, options);
}

}  // namespace dhr::server
