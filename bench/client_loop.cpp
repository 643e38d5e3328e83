#include "client_loop.hpp"

#include "bench_timing.hpp"
#include "plan/shipped_defaults.hpp"
#include "render/light_layout.hpp"
#include "render/warp_edges.hpp"
#include "render/warp_reference.hpp"
#include "scene/camera_bookmarks.hpp"

#include <glm/gtc/quaternion.hpp>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace dhr::bench {

FramePose moving_pose(const Pose& head, const Fov& fov, uint32_t i, uint32_t total) {
  const double yaw = glm::radians(60.0 / 90.0) * (static_cast<double>(i) - 0.5 * static_cast<double>(total));
  Pose moved = head;
  moved.orientation = glm::normalize(glm::angleAxis(yaw, glm::dvec3(0.0, 1.0, 0.0)) * head.orientation);
  moved.position += moved.orientation * glm::dvec3(0.0005 * static_cast<double>(i), 0.0, 0.0);
  FramePose pose;
  pose.frame = i;
  pose.display_time_ns = frame_time_ns(i);  // 90 Hz
  pose.scene_time_ns = pose.display_time_ns;
  for (uint32_t e = 0; e < 2; ++e) {
    // left_eye_pose moves by -ipd/2 along the head's x axis: a negative IPD gives the right eye.
    const double ipd = e == 0 ? kDefaultIpdMetres : -kDefaultIpdMetres;
    pose.views[e] = View{left_eye_pose(moved, ipd), fov};
  }
  return pose;
}

client::CoordinatorOptions shipped_options(bool discrete_gpu, bool soft_scene) {
  client::CoordinatorOptions o;
  o.plan.schedule = client::shipped::kSchedule;
  o.plan.x_max = client::shipped::kXMax;
  o.eye.warp =
      render::warp_settings_for(client::resolve_warp(client::shipped::kWarp, soft_scene), client::shipped::kDepthScale);
  o.eye.forward = client::forward_pass_for(client::shipped::kRenderPath, discrete_gpu);
  o.eye.frames_in_flight = 1;
  return o;
}

ClientLoop::ClientLoop(std::string name, const vk::Context& context, const render::ClientScene& scene, Extent size,
           server::VisibilityTracer& tracer, const TracedFormat& format, const client::CoordinatorOptions& options,
           const Pose& head, const Fov& fov, uint32_t total, int64_t scene_lead_ns)
    : name_(std::move(name)), context_(context), warp_(options.eye.warp), source_(tracer, format, scene_lead_ns),
      coordinator_(context, scene, size, source_, options), head_(head), fov_(fov), total_(total) {
  // The bits the warp passes mark (WarpSourceBuffers::upload): the hard fields of the warp's fields; none, no marks.
  const std::span<const SceneLight> fields(scene.field_lights());
  const size_t count = std::min<size_t>(fields.size(), kMaxLights);
  hard_bits_ = render::hard_field_bits(render::layout_for_lights(fields.first(count)));
  coordinator_.set_on_frame([this](const client::FrameRecord& r) { last_ = r; });
}

std::vector<double> ClientLoop::run(uint32_t i, uint32_t first_kept) {
  const size_t decoded_before = source_.decode_ms().size();
  const double busy_before = source_.busy_ms();
  const double busy_cpu_before = source_.busy_cpu_ms();
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_ms();
  const bool submitted = coordinator_.run_frame(client::FrameInput{moving_pose(head_, fov_, i, total_), false}, sink_);
  // Both without tracing and decoding (the source's).
  const double step_cpu_ms = thread_cpu_ms() - cpu_start - (source_.busy_cpu_ms() - busy_cpu_before);
  const double step_ms = ms_since(start) - (source_.busy_ms() - busy_before);
  if (!submitted || !coordinator_.finish()) throw std::runtime_error(name_ + ": " + coordinator_.last_error());
  if (i < first_kept) return {};
  record_ms_.push_back(step_cpu_ms / 2.0);
  record_wall_ms_.push_back(step_ms / 2.0);
  for (size_t k = decoded_before; k < source_.decode_ms().size(); ++k) {
    decode_ms_.push_back(source_.decode_ms()[k]);
    payload_bytes_.push_back(source_.payload_bytes()[k]);
  }
  std::vector<double> gpu;
  if (last_.eyes[0].stats.gpu.valid) {
    shadow_update_ms_.push_back(last_.eyes[0].stats.gpu.shadow_update_ms);
    shadow_update_lights_.push_back(last_.eyes[0].stats.shadow_update.lights);
  }
  for (uint32_t e = 0; e < 2; ++e) {
    const render::EyeStats& stats = last_.eyes[e].stats;
    traced_depth_frames_ += stats.traced_depth_rendered ? 1 : 0;
    older_frames_ += coordinator_.previous_visibility(e) ? 1 : 0;
    forward_frames_ += stats.forward ? 1 : 0;
    eye_frames_ += 1;
    if (stats.warp.surface() > 0) {
      known_frac_.push_back(static_cast<double>(stats.warp[render::WarpStatus::kKnown]) /
                            static_cast<double>(stats.warp.surface()));
      shadow_frac_.push_back(static_cast<double>(stats.warp.edges_shadow_map + stats.warp.filled_shadow_map) /
                             static_cast<double>(stats.warp.surface()));
    }
    if (!stats.gpu.valid) continue;
    gpu.push_back(stats.gpu.total_ms);
    traced_depth_ms_.push_back(stats.gpu.traced_depth_ms);
    measure_upload(e);
  }
  return gpu;
}

void ClientLoop::report(nlohmann::ordered_json& out) const {
  out[name_ + "_path"] = forward_frames_ == eye_frames_ ? "forward" : forward_frames_ == 0 ? "deferred" : "mixed";
  out[name_ + "_traced_depth_ms"] = median(traced_depth_ms_, std::nan(""));
  out[name_ + "_eye_frames"] = eye_frames_;  // measured, both eyes
  out[name_ + "_traced_depth_eye_frames"] = traced_depth_frames_;  // of those, with a traced depth rendered
  out[name_ + "_older_eye_frames"] = older_frames_;                // ... with a previous buffer held
  out[name_ + "_decode_ms"] = median(decode_ms_, std::nan(""));
  out[name_ + "_coded_bytes"] = median(payload_bytes_, std::nan(""));
  out[name_ + "_upload_ms"] = median(upload_ms_, std::nan(""));
  out[name_ + "_edge_marks_ms"] = median(edge_marks_ms_, std::nan(""));  // NaN without marks (band 0, no hard light)
  out[name_ + "_record_ms"] = median(record_ms_, std::nan(""));
  out[name_ + "_record_wall_ms"] = median(record_wall_ms_, std::nan(""));
  out[name_ + "_known_frac"] = median(known_frac_, std::nan(""));
  // Per frame (both eyes share it): the client's shadow maps re-rendered for moving casters and lights.
  out[name_ + "_shadow_update_ms"] = median(shadow_update_ms_, std::nan(""));
  out[name_ + "_shadow_update_lights"] = median(shadow_update_lights_, std::nan(""));
  // Mean and largest: where the maps only fill, the lights take turns (render::ShadowRefresh), so frames differ.
  out[name_ + "_shadow_update_mean_ms"] = mean(shadow_update_ms_, std::nan(""));
  out[name_ + "_shadow_update_max_ms"] = largest(shadow_update_ms_, std::nan(""));
  out[name_ + "_shadow_update_mean_lights"] = mean(shadow_update_lights_, std::nan(""));
  // Where the maps are looked up only for those pixels (with shadow_first they are looked up nearly everywhere).
  if (warp_.is_server_edges()) out[name_ + "_shadow_frac"] = median(shadow_frac_, std::nan(""));
}

void ClientLoop::measure_upload(uint32_t e) {
  const std::array<const std::optional<VisibilityFrame>*, 3> sources = {
      &coordinator_.visibility(e), warp_.other_eye ? &coordinator_.visibility(1 - e) : nullptr,
      warp_.older_buffer ? &coordinator_.previous_visibility(e) : nullptr};
  double ms = 0.0, marks_ms = 0.0;
  for (size_t s = 0; s < sources.size(); ++s) {
    if (sources[s] == nullptr || !*sources[s]) continue;
    const VisibilityBuffer& buffer = (*sources[s])->buffer;
    const VkDeviceSize bytes = (buffer.size_bytes() + 3) / 4 * 4;
    if (!upload_[s] || upload_[s].size() < bytes) {
      upload_[s] = vk::Buffer(context_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    }
    const auto start = std::chrono::steady_clock::now();
    upload_[s].write(buffer.data.data(), buffer.data.size());
    ms += ms_since(start);
    if (marks_due()) {  // the marks the warp passes compute with each upload
      const auto marks_start = std::chrono::steady_clock::now();
      const VisibilityFrame& frame = **sources[s];
      const std::span<const uint8_t> rows = frame.complete ? std::span<const uint8_t>{} : frame.row_valid;
      const VisibilityBuffer marks = render::edge_band_marks(buffer, rows, warp_.edge_band, hard_bits_);
      marks_ms += ms_since(marks_start);
      if (marks.data.empty()) throw std::logic_error("edge band marks: empty");
    }
  }
  upload_ms_.push_back(ms);
  if (marks_due()) edge_marks_ms_.push_back(marks_ms);
}

}  // namespace dhr::bench
