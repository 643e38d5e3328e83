#include "render/eye_pipeline.hpp"

#include <algorithm>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>
#include <stdexcept>

#include "render/client_scene.hpp"
#include "render/client_motion.hpp"
#include "render/light_layout.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::render {
namespace {

enum Timestamp : uint32_t { kStart = 0, kAfterGBuffer, kAfterWarp, kAfterShading, kTimestampCount };
enum PrepareTimestamp : uint32_t { kPrepareStart = 0, kPrepareEnd, kPrepareCount };

bool same_camera(const Camera& a, const Camera& b) {
  return a.T_world_eye.position == b.T_world_eye.position && a.T_world_eye.orientation == b.T_world_eye.orientation &&
         a.tangents.left == b.tangents.left && a.tangents.right == b.tangents.right &&
         a.tangents.up == b.tangents.up && a.tangents.down == b.tangents.down && a.extent == b.extent;
}

uint32_t checked_slots(const EyePipelineOptions& options) {
  if (options.frames_in_flight == 0) throw std::invalid_argument("EyePipeline needs frames_in_flight >= 1");
  return options.frames_in_flight;
}

}  // namespace

EyePipeline::EyePipeline(const vk::Context& context, const ClientScene& scene, Extent extent,
                         const EyePipelineOptions& options)
    : context_(&context),
      scene_(&scene),
      extent_(extent),
      options_(options),
      gbuffer_pass_(context, scene),
      warp_pass_(context, checked_slots(options)),
      shading_pass_(context, checked_slots(options), &scene.light_slots()) {
  if (extent.width == 0 || extent.height == 0) throw std::invalid_argument("EyePipeline: zero extent");
  if (options.forward) {  // made here: its constructor submits work, which record() (inside a recording) cannot
    ForwardOptions fo;
    fo.mode = ForwardMode::kPaperWarp;
    fo.write_mask = options.forward_mask;
    fo.slots = options.frames_in_flight;
    forward_pass_ = std::make_unique<ForwardPass>(context, scene, fo);
  }
  create_images();
  slots_.resize(options.frames_in_flight);
  for (Slot& s : slots_) {
    s.timestamps = vk::TimestampQueries(context, kTimestampCount);
    s.prepare_timestamps = vk::TimestampQueries(context, kPrepareCount);
  }
}

EyePipeline::~EyePipeline() = default;

// The forward targets are made with the pipeline (the default path); the deferred ones on the deferred
// path's first use.
void EyePipeline::create_images() {
  ForwardOptions fo;
  fo.write_mask = options_.forward_mask;
  forward_ = ForwardTargets::create(*context_, extent_, fo);
  deferred_images_ = false;
  last_display_.reset();
  last_display_depth_ = nullptr;
  gbuffer_ = GBuffer{};
  warp_ = WarpTargets{};
  output_ = vk::Image{};
}

void EyePipeline::ensure_deferred_images() {
  if (deferred_images_) return;
  gbuffer_ = GBuffer::create(*context_, extent_);
  const std::span<const SceneLight> lights(scene_->lights());
  const bool soft = layout_for_lights(lights.first(std::min<size_t>(lights.size(), kMaxLights))).any_soft();
  warp_ = WarpTargets::create(*context_, extent_, WarpOutputs{options_.warp_status, options_.motion_vectors, soft});
  output_ = create_shading_output(*context_, extent_);
  deferred_images_ = true;
}

bool EyePipeline::uses_forward() const {
  const WarpSettings& w = options_.warp;
  const bool paper = !w.bilinear && !w.depth_test && !w.other_eye && !w.older_buffer && !w.neighbour_fill &&
                     !w.uses_shadow_maps();
  return options_.forward && (paper || w.is_server_edges()) && options_.shading.view == ShadingView::kShaded &&
         !options_.motion_vectors && !options_.warp_status && scene_->lights().size() <= options_.forward_max_lights &&
         scene_->light_slots().is_identity();  // the forward pass shades lights by index, not by slot
}

vk::Image& EyePipeline::output() {
  if (last_forward_ || !deferred_images_) return forward_.colour;
  return output_;
}

vk::Image& EyePipeline::mask() {
  if (last_forward_ || !deferred_images_) return forward_.mask;
  return warp_.mask;
}

void EyePipeline::resize(Extent extent) {
  if (extent == extent_) return;
  if (extent.width == 0 || extent.height == 0) throw std::invalid_argument("EyePipeline::resize: zero extent");
  DHR_VK_CHECK(vkDeviceWaitIdle(context_->device()));
  extent_ = extent;
  create_images();
}

void EyePipeline::prepare(VkCommandBuffer cmd, uint32_t slot_index, const VisibilityInput& visibility,
                          const VisibilityInput* older) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("EyePipeline::prepare: slot out of range");
  Slot& slot = slots_[slot_index];
  slot.traced_depth_rendered = false;
  if (!options_.warp.depth_test) return;
  // The depth cameras needed this frame: the newest's, then the previous one's (with the older-buffer fill).
  std::array<std::optional<Camera>, 2> wanted;
  if (visibility.buffer != nullptr && !validate_camera(visibility.traced)) {
    wanted[0] = depth_camera(visibility.traced, options_.warp.depth_scale);
  }
  if (options_.warp.older_buffer && older != nullptr && older->buffer != nullptr && !validate_camera(older->traced)) {
    wanted[1] = depth_camera(older->traced, options_.warp.depth_scale);
  }
  const std::array<const Camera*, 2> needed{wanted[0] ? &*wanted[0] : nullptr, wanted[1] ? &*wanted[1] : nullptr};
  const bool splat = options_.warp.depth_splat;
  auto holds = [&](size_t k, const Camera* camera) {
    return camera != nullptr && traced_camera_[k] && traced_splat_[k] == splat &&
           same_camera(*traced_camera_[k], *camera);
  };
  // The splat's source: this eye's previous display frame (none yet: no traced depth, no test this frame).
  if (splat && !last_display_) return;
  bool started = false;
  for (size_t n = 0; n < needed.size(); ++n) {
    const Camera* camera = needed[n];
    if (camera == nullptr || holds(0, camera) || holds(1, camera)) continue;
    // Without the older-buffer fill one G-buffer suffices; with it, overwrite the one the other needed camera
    // does not occupy (else the one not rendered last: the newest so far becomes the previous).
    const Camera* keep = needed[1 - n];
    const size_t target = !options_.warp.older_buffer ? 0 : holds(0, keep) ? 1 : holds(1, keep) ? 0 : 1 - newest_;
    const Extent extent = camera->extent;
    GBuffer& g = traced_[target];
    if (!g.depth || !(g.extent() == extent)) g = GBuffer::create(*context_, extent);
    if (!started) {
      slot.prepare_timestamps.reset(cmd);
      slot.prepare_timestamps.write(cmd, kPrepareStart);
      started = true;
    }
    if (splat) {
      if (!splat_) splat_ = std::make_unique<TracedDepthSplat>(*context_, options_.frames_in_flight, 2);
      splat_->record(cmd, slot_index, static_cast<uint32_t>(n), *last_display_depth_, *last_display_, g.depth,
                     *camera, options_.near_plane);
    } else {
      gbuffer_pass_.record(cmd, g, *camera, options_.near_plane);
    }
    traced_camera_[target] = *camera;
    traced_splat_[target] = splat;
    if (n == 0) newest_ = target;
  }
  if (started) {
    slot.prepare_timestamps.write(cmd, kPrepareEnd);
    slot.traced_depth_rendered = true;
  }
}

vk::Image* EyePipeline::traced_depth(const Camera& traced) {
  const Camera depth = depth_camera(traced, options_.warp.depth_scale);
  for (size_t k = 0; k < traced_.size(); ++k) {
    if (traced_camera_[k] && traced_splat_[k] == options_.warp.depth_splat && same_camera(*traced_camera_[k], depth)) {
      return &traced_[k].depth;
    }
  }
  return nullptr;
}

const shader::ClientWarpMotion* EyePipeline::warp_motion(const Camera& display, std::span<const SceneLight> lights,
                                                         const VisibilityInput& visibility,
                                                         const WarpSourceInput& other, const VisibilityInput* older,
                                                         const MovedScene* moved) {
  const ClientMotion& motion = scene_->motion();
  if (!options_.warp.motion || moved == nullptr || !moved->sampled || !motion.animated()) return nullptr;
  const auto time_of = [](const VisibilityInput* in) -> std::optional<double> {
    if (in == nullptr || in->buffer == nullptr) return std::nullopt;
    return scene_seconds(in->scene_time_ns);
  };
  WarpMotionInput in;
  in.motion = &motion.scene_motion();
  in.display_time = moved->time_s;
  in.overrides = moved->overrides;
  // The forward pass reads source 0 only: the others' motion is not sampled.
  const bool forward = uses_forward();
  in.source_times = {time_of(&visibility), forward ? std::nullopt : time_of(other.visibility),
                     forward ? std::nullopt : time_of(older)};
  in.lights = lights;
  // Moving lights keep their extents: the rest lights' layout is the layout at any time (made once).
  if (!motion_layout_) motion_layout_ = layout_for_lights(lights.first(std::min<size_t>(lights.size(), kMaxLights)));
  in.layout = *motion_layout_;
  in.eye = display.T_world_eye.position;
  // Past every surface: twice the scene's diagonal (moving meshes stay near their rest bounds).
  in.far_distance = 2.0 * glm::length(glm::dvec3(scene_->bounds().size())) + 1.0;
  make_warp_motion(in, motion_boxes_, warp_motion_);
  return &warp_motion_;
}

void EyePipeline::record(VkCommandBuffer cmd, uint32_t slot_index, const View& view,
                         const VisibilityInput& visibility, const WarpSourceInput& other,
                         const ShadowMaps* shadow_maps, const VisibilityInput* older, const MovedScene* moved) {
  if (slot_index >= slots_.size()) throw std::invalid_argument("EyePipeline::record: slot out of range");
  Slot& slot = slots_[slot_index];
  const Camera camera = display_camera(view, extent_);
  const double near_plane = options_.near_plane;
  const std::span<const SceneLight> lights =
      moved != nullptr && moved->sampled ? std::span<const SceneLight>(moved->lights) : scene_->lights();

  const shader::ClientWarpMotion* motion = warp_motion(camera, lights, visibility, other, older, moved);

  slot.timestamps.reset(cmd);
  slot.timestamps.write(cmd, kStart);
  slot.forward = uses_forward();
  last_forward_ = slot.forward;
  if (slot.forward) {
    ForwardFrame frame;
    frame.display = camera;
    frame.near_plane = near_plane;
    frame.visibility = &visibility;
    frame.shadow_maps = shadow_maps;
    frame.lights = lights;
    frame.moved = moved;
    frame.motion = motion;
    frame.shading = options_.shading;
    const bool edges = options_.warp.is_server_edges();
    if (edges) frame.edge_band = options_.warp.edge_band;
    frame.soft_refine = edges && options_.warp.soft_refine;
    if (edges && options_.warp.depth_test && visibility.buffer != nullptr) {
      frame.traced_depth = traced_depth(visibility.traced);
      frame.depth_test = options_.warp;
    }
    // The settings may change between frames (warp_settings()); both warp modes share the pipelines.
    forward_pass_->set_mode(edges ? ForwardMode::kServerEdges : ForwardMode::kPaperWarp);
    const ForwardPass::Recorded r = forward_pass_->record(cmd, slot_index, frame, forward_);
    slot.draws = r.draws;
    slot.visibility_used = r.visibility_used;
    slot.timestamps.write(cmd, kAfterGBuffer);
    slot.timestamps.write(cmd, kAfterWarp);
    slot.timestamps.write(cmd, kAfterShading);
    slot.recorded = true;
    last_display_ = camera;
    last_display_depth_ = &forward_.depth;
    return;
  }
  ensure_deferred_images();
  slot.draws = gbuffer_pass_.record(cmd, gbuffer_, camera, near_plane, moved);
  slot.timestamps.write(cmd, kAfterGBuffer);
  WarpFrame frame;
  frame.depth = &gbuffer_.depth;
  frame.normal = &gbuffer_.normal;
  frame.display = camera;
  frame.near_plane = near_plane;
  frame.sources[0].visibility = &visibility;
  frame.sources[0].traced_depth =
      options_.warp.depth_test && visibility.buffer != nullptr ? traced_depth(visibility.traced) : nullptr;
  frame.sources[1] = other;
  if (older != nullptr) {
    frame.sources[2].visibility = older;
    frame.sources[2].traced_depth =
        options_.warp.depth_test && older->buffer != nullptr ? traced_depth(older->traced) : nullptr;
  }
  frame.shadow_maps = shadow_maps;
  // With light slots the warp blends fields: it is given one light per field (their count and kinds); the
  // client's shadow maps hold at most kMaxLights lights and are not made for such a scene.
  const bool slots = !scene_->light_slots().is_identity();
  if (slots && shadow_maps != nullptr)
    throw std::invalid_argument("EyePipeline::record: shadow maps for a scene whose lights share light slots");
  frame.lights = slots ? std::span<const SceneLight>(scene_->field_lights()) : lights;
  frame.settings = options_.warp;
  frame.motion = motion;
  slot.visibility_used = warp_pass_.record(cmd, slot_index, frame, warp_) && visibility.buffer != nullptr;
  slot.timestamps.write(cmd, kAfterWarp);
  shading_pass_.record(cmd, slot_index, gbuffer_, warp_, camera, near_plane, lights,
                       options_.shading, output_);
  slot.timestamps.write(cmd, kAfterShading);
  slot.recorded = true;
  last_display_ = camera;
  last_display_depth_ = &gbuffer_.depth;
}

EyeStats EyePipeline::read_stats(uint32_t slot_index) const {
  if (slot_index >= slots_.size()) throw std::invalid_argument("EyePipeline::read_stats: slot out of range");
  const Slot& slot = slots_[slot_index];
  EyeStats stats;
  stats.extent = extent_;
  if (!slot.recorded) return stats;
  stats.draws = slot.draws;
  stats.visibility_used = slot.visibility_used;
  stats.forward = slot.forward;
  stats.warp = slot.forward ? forward_pass_->read_counts(slot_index) : warp_pass_.read_counts(slot_index);
  stats.traced_depth_rendered = slot.traced_depth_rendered;
  if (slot.traced_depth_rendered) {
    const std::vector<double> pns = slot.prepare_timestamps.read_ns();
    if (pns.size() == kPrepareCount) stats.gpu.traced_depth_ms = (pns[kPrepareEnd] - pns[kPrepareStart]) * 1e-6;
  }
  const std::vector<double> ns = slot.timestamps.read_ns();
  if (ns.size() == kTimestampCount) {
    stats.gpu.valid = true;
    if (slot.forward) {
      stats.gpu.forward_ms = (ns[kAfterGBuffer] - ns[kStart]) * 1e-6;
      stats.gpu.total_ms = (ns[kAfterShading] - ns[kStart]) * 1e-6 + stats.gpu.traced_depth_ms;
      return stats;
    }
    stats.gpu.gbuffer_ms = (ns[kAfterGBuffer] - ns[kStart]) * 1e-6;
    stats.gpu.warp_ms = (ns[kAfterWarp] - ns[kAfterGBuffer]) * 1e-6;
    stats.gpu.shading_ms = (ns[kAfterShading] - ns[kAfterWarp]) * 1e-6;
    stats.gpu.total_ms = (ns[kAfterShading] - ns[kStart]) * 1e-6 + stats.gpu.traced_depth_ms;
  }
  return stats;
}

}  // namespace dhr::render
