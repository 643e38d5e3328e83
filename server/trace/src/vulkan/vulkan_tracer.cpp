#include "trace/vulkan/vulkan_tracer.hpp"

#include "trace/ray_offset.hpp"
#include "trace/soft/soft_visibility.hpp"
#include "trace/vulkan/vulkan_tracer_internal.hpp"
#include "scene/node_overrides.hpp"

#include "log/log.hpp"
#include "vk/barriers.hpp"
#include "vk/timestamps.hpp"

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <stdexcept>

namespace dhr::server {

// The GLSL side uses shader_interface.h's copies of the shadow-ray constants: keep them identical.
static_assert(shader::kVisRayOffsetOriginThreshold == kRayOffsetOriginThreshold);
static_assert(shader::kVisRayOffsetFloatScale == kRayOffsetFloatScale);
static_assert(shader::kVisRayOffsetIntScale == kRayOffsetIntScale);
static_assert(kMaxLights <= 32, "one 32-bit mask per pixel on the GPU");
static_assert(shader::kVisSoftFieldBits == kSoftLevelBits && shader::kVisSoftLevels == kDefaultSoftLevels);

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::unique_ptr<vk::Context> create_context(const TracerOptions& options) {
  vk::ContextOptions context_options;
  context_options.app_name = "dhr-server";
  try {
    context_options.device = vk::parse_device_preference(options.vk_device);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("vulkan tracer: ") + e.what());
  }
  context_options.require_ray_tracing = true;
  context_options.validation = options.vk_validation;
  try {
    return vk::Context::create(context_options);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("vulkan tracer: ") + e.what());
  }
}

shader::VisPushConstants push_constants(const Camera& camera, const glm::dvec3& origin) {
  shader::VisPushConstants pc{};
  const glm::vec3 eye(camera.T_world_eye.position - origin);
  pc.eye_x = eye.x;
  pc.eye_y = eye.y;
  pc.eye_z = eye.z;
  const glm::dmat3 R = glm::mat3_cast(glm::normalize(camera.T_world_eye.orientation));
  pc.axis_x_x = float(R[0].x);
  pc.axis_x_y = float(R[0].y);
  pc.axis_x_z = float(R[0].z);
  pc.axis_y_x = float(R[1].x);
  pc.axis_y_y = float(R[1].y);
  pc.axis_y_z = float(R[1].z);
  pc.axis_z_x = float(R[2].x);
  pc.axis_z_y = float(R[2].y);
  pc.axis_z_z = float(R[2].z);
  pc.tan_left = float(camera.tangents.left);
  pc.tan_up = float(camera.tangents.up);
  pc.tan_step_x = float(camera.tangents.width() / camera.extent.width);
  pc.tan_step_y = float(camera.tangents.height() / camera.extent.height);
  pc.width = camera.extent.width;
  pc.height = camera.extent.height;
  return pc;
}

// Packs the GPU's 32-bit masks into the buffer's 8/16/32-bit little-endian layout.
void pack_masks(const uint32_t* masks, VisibilityBuffer& out) {
  const size_t n = out.pixel_count();
  uint8_t* dst = out.data.data();
  switch (out.mask_bits) {
    case MaskWidth::k8:
      for (size_t i = 0; i < n; ++i) dst[i] = static_cast<uint8_t>(masks[i]);
      break;
    case MaskWidth::k16:
      for (size_t i = 0; i < n; ++i) store_mask(dst + 2 * i, 2, masks[i]);
      break;
    case MaskWidth::k32:
      for (size_t i = 0; i < n; ++i) store_mask(dst + 4 * i, 4, masks[i]);
      break;
  }
}

// Bit i: light i has a level field. The shader places fields from these bits alone (in the lights' order, without
// gaps, as VisibilityLayout lays them out); a layout laid out otherwise is a programming error.
uint32_t soft_light_bits(const VisibilityLayout& layout) {
  uint32_t soft = 0, next = 0;
  for (uint32_t i = 0; i < layout.light_count; ++i) {
    if (layout.offset[i] != next || (layout.bits[i] != 1 && layout.bits[i] != shader::kVisSoftFieldBits))
      throw std::logic_error("vulkan tracer: a mask layout whose fields are not consecutive");
    if (layout.is_soft(i)) soft |= 1u << i;
    next += layout.bits[i];
  }
  return soft;
}

}  // namespace

struct VulkanTracer::Impl {
  std::unique_ptr<vk::Context> context;  // first: destroyed last
  TracerOptions options;
  VulkanTracerConfig config;
  std::vector<SceneLight> lights;
  LightSlots slots;  // the identity for at most kMaxLights lights
  SoftOptions soft;  // the soft fields' sampling: the defaults (the shader implements SoftPattern::kPerLight only)
  glm::dvec3 origin{0.0};
  float ray_offset_scale = 1.0f;  // ray_offset.hpp, for the scene's bounds
  detail::GpuScene scene;
  detail::TracerPipeline pipeline;
  vk::TimestampQueries timestamps;
  vk::Buffer masks_device;  // written by the shader
  vk::Buffer masks_host;    // host-visible (cached where possible) copy for readback
  vk::Buffer counters;      // host-visible statistics counters
  size_t capacity_pixels = 0;
  std::string description;
  detail::GpuMotion motion;  // what moves (empty for a static scene)
  double last_motion_update_ms = 0.0;
  std::mutex mutex;

  void ensure_frame_buffers(size_t pixels);
  void record(VkCommandBuffer cmd, const shader::VisPushConstants& pc, size_t pixels) const;
};

void VulkanTracer::Impl::ensure_frame_buffers(size_t pixels) {
  if (pixels <= capacity_pixels) return;
  const VkDeviceSize bytes = pixels * sizeof(uint32_t);
  masks_device = vk::Buffer(*context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  try {
    masks_host = vk::Buffer(*context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  } catch (const std::runtime_error&) {  // no cached host memory: uncached reads are slower, still right
    masks_host = vk::Buffer(*context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  }
  if (!counters) {
    counters = vk::Buffer(*context, shader::kVisCounterSlots * shader::kVisCounterStride * sizeof(uint32_t),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  }
  detail::write_frame_descriptors(*context, pipeline, masks_device, counters);
  capacity_pixels = pixels;
}

void VulkanTracer::Impl::record(VkCommandBuffer cmd, const shader::VisPushConstants& pc, size_t pixels) const {
  timestamps.reset(cmd);
  vkCmdFillBuffer(cmd, counters.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  timestamps.write(cmd, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
  pipeline.pipeline.bind(cmd);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline.layout.get(), 0, 1, &pipeline.set, 0,
                          nullptr);
  vkCmdPushConstants(cmd, pipeline.layout.get(), VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof pc, &pc);
  pipeline.pipeline.trace(cmd, pc.width, pc.height);
  timestamps.write(cmd, 1, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, 0, pixels * sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, masks_device.handle(), masks_host.handle(), 1, &region);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

VulkanTracer::VulkanTracer(const Scene& scene, const TracerOptions& options, const VulkanTracerConfig& config)
    : impl_(std::make_unique<Impl>()) {
  if (scene.lights.size() > kMaxSlotLights)
    throw std::runtime_error("vulkan tracer: " + std::to_string(scene.lights.size()) + " lights, at most " +
                             std::to_string(kMaxSlotLights) + " supported");
  Impl& im = *impl_;
  // More than kMaxLights lights share the mask's fields (scene/light_slots.hpp), placed where they stand at rest.
  try {
    im.slots = LightSlots::assign(scene.lights);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("vulkan tracer: ") + e.what());
  }
  if (!im.slots.is_identity() && !scene.animation.empty())
    throw std::runtime_error("vulkan tracer: " + std::to_string(scene.lights.size()) +
                             " lights share light slots, which need a scene without animation (more than " +
                             std::to_string(kMaxLights) + " lights in a moving scene are not supported)");
  im.options = options;
  im.config = config;
  im.lights = scene.lights;
  im.context = create_context(options);
  const vk::DeviceInfo& info = im.context->info();
  im.description = info.name + ", " + (info.driver_info.empty() ? info.driver_name : info.driver_info);

  const auto t0 = std::chrono::steady_clock::now();
  const detail::ScenePlan plan = detail::plan_gpu_scene(scene, config);
  const double plan_ms = ms_since(t0);
  im.origin = plan.origin;
  im.ray_offset_scale = ray_offset_scale(scene.bounds);
  const std::vector<PackedLight> packed = pack_lights(im.lights, im.origin);
  const std::vector<shader::VisSoftLight> extents = detail::soft_light_records(im.lights, im.origin, im.soft.salt);
  im.scene = detail::upload_gpu_scene(*im.context, plan, packed, extents, im.slots.gpu_words(im.origin),
                                      config);
  im.scene.stats.build_ms += plan_ms;  // the spatial sort is part of building
  im.motion = detail::plan_gpu_motion(scene, plan);
  log::debug("vulkan tracer: scene plan (validation, instancing, Morton sort) %.1f ms", plan_ms);

  im.pipeline = detail::create_tracer_pipeline(*im.context);
  if (im.scene.tlas) detail::write_scene_descriptors(*im.context, im.pipeline, im.scene);
  im.timestamps = vk::TimestampQueries(*im.context, 2);
}

VulkanTracer::~VulkanTracer() = default;

std::string VulkanTracer::device_description() const { return impl_->description; }
const AccelStats& VulkanTracer::accel_stats() const { return impl_->scene.stats; }
uint32_t VulkanTracer::light_count() const { return impl_->slots.slot_count(); }
const LightSlots* VulkanTracer::light_slots() const { return impl_->slots.is_identity() ? nullptr : &impl_->slots; }

std::vector<bool> VulkanTracer::light_extents() const {
  return impl_->slots.soft_slots();  // the identity's: each light's extent
}
void VulkanTracer::set_scene_time(double t, const NodeOverrides* overrides) {
  Impl& im = *impl_;
  if (im.motion.meta.animation.empty()) return;
  const auto t0 = std::chrono::steady_clock::now();
  std::lock_guard lock(im.mutex);
  const detail::GpuMotionUpdate update =
      detail::move_gpu_scene(*im.context, im.scene, im.motion, im.origin, t, overrides, im.soft.salt);
  if (update.moved_lights > 0) im.lights = im.motion.lights;  // light culling sees them where they are
  im.last_motion_update_ms = ms_since(t0);
}

bool VulkanTracer::moves() const { return !impl_->motion.meta.animation.empty(); }
double VulkanTracer::last_motion_update_ms() const { return impl_->last_motion_update_ms; }
const SceneAnimation* VulkanTracer::scene_animation() const {
  return moves() ? &impl_->motion.meta.animation : nullptr;
}

const VulkanTracerConfig& VulkanTracer::config() const { return impl_->config; }
bool VulkanTracer::is_cpu_device() const { return impl_->context->info().is_cpu; }
uint32_t VulkanTracer::validation_error_count() const { return impl_->context->validation_error_count(); }

void VulkanTracer::trace(const Camera& camera, VisibilityBuffer& out, TraceStats& out_stats) {
  trace_lights(camera, light_count(), out, out_stats);
}

void VulkanTracer::trace_lights(const Camera& camera, uint32_t lights, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  trace_fields(camera, VisibilityLayout::hard(std::min(lights, light_count())), out, out_stats);
}

void VulkanTracer::trace_layout(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  trace_fields(camera, layout, out, out_stats);
}

void VulkanTracer::trace_fields(const Camera& camera, const VisibilityLayout& layout, VisibilityBuffer& out,
                                TraceStats& out_stats) {
  const auto t0 = std::chrono::steady_clock::now();
  check_trace_request(camera, layout, light_count());
  Impl& im = *impl_;
  std::lock_guard lock(im.mutex);

  const uint32_t width = camera.extent.width, height = camera.extent.height;
  const uint32_t lights = layout.light_count, bits = layout.total_bits();
  if (out.width != width || out.height != height || out.light_count != bits)
    out = VisibilityBuffer::create(width, height, bits);
  const size_t pixels = out.pixel_count();

  shader::VisPushConstants pc = push_constants(camera, im.origin);
  pc.light_count = lights;  // the shader's light loop: unrequested lights are never tested
  pc.soft_lights = soft_light_bits(layout);
  pc.soft_initial_samples = im.soft.initial_samples;
  pc.soft_max_samples = im.soft.max_samples;
  pc.ray_offset_scale = im.ray_offset_scale;
  pc.primary_near = static_cast<float>(im.options.primary_near);
  TraceStats stats;
  stats.pixels = pixels;
  stats.lights_unrequested = light_count() - lights;
  // With light slots every requested field is traced (a light its view cannot reach is out of range or
  // back-facing at every pixel, so its field is 1 as the Embree backend's culled light's is; only the counts
  // differ: rays or out-of-range skips here where Embree counts skipped_culled_light).
  const bool slots = !im.slots.is_identity();
  for (uint32_t i = 0; i < lights; ++i) {
    if (!slots && im.options.skip.cull_lights && !light_may_reach_view(im.lights[i], camera))
      ++stats.lights_culled;
    else
      pc.active_lights |= 1u << i;
  }
  pc.flags = (im.options.skip.backfacing ? shader::kVisSkipBackfacing : 0u) |
             (im.options.skip.out_of_range ? shader::kVisSkipOutOfRange : 0u) | (slots ? shader::kVisLightSlots : 0u);

  if (!im.scene.tlas) {  // no triangles: every primary ray misses
    std::fill(out.data.begin(), out.data.end(), uint8_t{0});
    stats.primary_rays = pixels;
    stats.background_pixels = pixels;
    stats.trace_ms = ms_since(t0);
    out_stats = stats;
    return;
  }

  im.ensure_frame_buffers(pixels);
  im.context->submit_and_wait([&](VkCommandBuffer cmd) { im.record(cmd, pc, pixels); });

  std::vector<uint32_t> counters(shader::kVisCounterSlots * shader::kVisCounterStride);
  im.counters.read(counters.data(), counters.size() * sizeof(uint32_t));
  for (uint32_t s = 0; s < shader::kVisCounterSlots; ++s) {
    const uint32_t* c = &counters[s * shader::kVisCounterStride];
    stats.primary_rays += c[shader::kVisCounterPrimary];
    stats.background_pixels += c[shader::kVisCounterBackground];
    stats.shadow_rays += c[shader::kVisCounterShadow];
    stats.skipped_backfacing += c[shader::kVisCounterSkippedBackfacing];
    stats.skipped_out_of_range += c[shader::kVisCounterSkippedOutOfRange];
    stats.soft_pairs += c[shader::kVisCounterSoftPairs];
    stats.soft_contributing_pairs += c[shader::kVisCounterSoftContributing];
    stats.soft_refined_pairs += c[shader::kVisCounterSoftRefined];
    stats.soft_shadow_rays += c[shader::kVisCounterSoftShadow];
  }
  stats.skipped_culled_light = (stats.pixels - stats.background_pixels) * stats.lights_culled;

  if (im.masks_host.memory_flags() & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) {
    pack_masks(static_cast<const uint32_t*>(im.masks_host.mapped()), out);
  } else {
    std::vector<uint32_t> masks(pixels);
    im.masks_host.read(masks.data(), pixels * sizeof(uint32_t));
    pack_masks(masks.data(), out);
  }

  if (im.timestamps.supported()) {
    const std::vector<double> ns = im.timestamps.read_ns();
    stats.gpu_ms = ns[1] * 1e-6;
  }
  stats.trace_ms = ms_since(t0);
  out_stats = stats;
}

std::unique_ptr<VisibilityTracer> create_vulkan_tracer(const Scene& scene, const TracerOptions& options,
                                                       const VulkanTracerConfig& config) {
  return std::make_unique<VulkanTracer>(scene, options, config);
}

}  // namespace dhr::server
