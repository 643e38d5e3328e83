#include "sink/png_sink.hpp"

#include <filesystem>
#include <stdexcept>

#include "frame/frame_coordinator.hpp"
#include "traces/shown_frame.hpp"

namespace dhr::client {

void PngSink::describe(const FrameCoordinator& coordinator, std::string warp, std::string view) {
  const std::string path = (std::filesystem::path(sink_.directory()) / kShownFramesFile).string();
  views_.open(path, std::ios::binary | std::ios::trunc);
  if (!views_) throw std::runtime_error("cannot create " + path);
  coordinator_ = &coordinator;
  warp_ = std::move(warp);
  view_ = std::move(view);
}

void PngSink::after_submit(uint64_t frame, const EyeImages& eyes) {
  if (!sink_.wants(frame)) return;
  ShownFrame shown;
  for (uint32_t e = 0; e < 2; ++e) {
    const std::optional<std::string> path = sink_.write(frame, e, *eyes[e]);
    if (path) shown.eyes[e].file = std::filesystem::path(*path).filename().string();
  }
  if (coordinator_ == nullptr) return;
  // The coordinator calls after_submit right after submitting this frame: its views and plan are this frame's.
  const FrameRecord& record = coordinator_->last_submitted();
  shown.frame = frame;
  shown.scene_time_ns = record.scene_time_ns;
  shown.eye_size = coordinator_->eye_extent();
  if (const std::optional<VisibilityFormat> format = coordinator_->visibility_format()) {
    shown.traced = format->traced;
    if (format->scene_hash != 0) shown.scene_hash = format->scene_hash;
  }
  shown.render_path = coordinator_->eye(0).uses_forward() ? "forward" : "deferred";
  shown.warp = warp_;
  shown.view = view_;
  for (uint32_t e = 0; e < 2; ++e) {
    ShownEye& eye = shown.eyes[e];
    const EyeFrameRecord& r = record.eyes[e];
    eye.view = coordinator_->rendered_views()[e];
    eye.has_visibility = r.has_visibility;
    eye.visibility_frame = r.visibility_frame;
    eye.age = r.age;
    eye.complete = r.complete;
  }
  views_ << shown_frame_json(shown) << '\n';
  views_.flush();
  if (!views_) throw std::runtime_error("cannot write " + sink_.directory() + "/" + kShownFramesFile);
}

}  // namespace dhr::client
