// Offscreen frame sink: both eyes as PNG files every Nth frame (render::OffscreenPngSink; blocking readback,
// for people and tests, not for the headset's rate). With describe(), each saved frame also gets a line in
// <directory>/views.jsonl (traces/shown_frame.hpp): its views exactly as rendered, so `dhr-eval compare` can
// render the exact shading for the same pose.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include "frame/frame_sink.hpp"
#include "render/offscreen_sink.hpp"

namespace dhr::client {

class FrameCoordinator;

class PngSink final : public FrameSink {
 public:
  // Throws std::runtime_error when the directory cannot be created.
  PngSink(const vk::Context& context, const std::string& directory, uint32_t every_nth, bool swap_red_blue = false)
      : sink_(context, directory, every_nth, swap_red_blue) {}
  // Starts <directory>/views.jsonl (replacing an older one) for the frames `coordinator` renders; `warp` and
  // `view` name the run's settings. Throws std::runtime_error when the file cannot be created.
  void describe(const FrameCoordinator& coordinator, std::string warp, std::string view);

  void after_submit(uint64_t frame, const EyeImages& eyes) override;
  uint64_t files_written() const { return sink_.files_written(); }
  const std::string& directory() const { return sink_.directory(); }

 private:
  render::OffscreenPngSink sink_;
  const FrameCoordinator* coordinator_ = nullptr;
  std::string warp_, view_;
  std::ofstream views_;
};

// Several sinks in order (e.g. the swapchain and PNG snapshots of it).
class SinkList final : public FrameSink {
 public:
  void add(FrameSink& sink) { sinks_.push_back(&sink); }
  void record(VkCommandBuffer cmd, uint64_t frame, const EyeImages& eyes) override {
    for (FrameSink* s : sinks_) s->record(cmd, frame, eyes);
  }
  void after_submit(uint64_t frame, const EyeImages& eyes) override {
    for (FrameSink* s : sinks_) s->after_submit(frame, eyes);
  }

 private:
  std::vector<FrameSink*> sinks_;
};

}  // namespace dhr::client
