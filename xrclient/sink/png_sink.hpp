// Offscreen frame sink: both eyes as PNG files every Nth frame (render::OffscreenPngSink; blocking readback,
// for people and tests, not for the headset's rate).
#pragma once
#include <string>
#include <vector>

#include "frame/frame_sink.hpp"
#include "render/offscreen_sink.hpp"

namespace dhr::client {

class PngSink final : public FrameSink {
 public:
  // Throws std::runtime_error when the directory cannot be created.
  PngSink(const vk::Context& context, const std::string& directory, uint32_t every_nth)
      : sink_(context, directory, every_nth) {}
  void after_submit(uint64_t frame, const EyeImages& eyes) override {
    if (!sink_.wants(frame)) return;
    for (uint32_t e = 0; e < 2; ++e) sink_.write(frame, e, *eyes[e]);
  }
  uint64_t files_written() const { return sink_.files_written(); }
  const std::string& directory() const { return sink_.directory(); }

 private:
  render::OffscreenPngSink sink_;
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
