// What the frame loop knows about one frame once its GPU work completed, and the run's summary.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/eye_pipeline.hpp"

namespace dhr::client {

struct EyeFrameRecord {
  bool has_visibility = false;
  uint64_t visibility_frame = 0;  // frame the used buffer was traced for
  uint64_t display_frame = 0;     // whose pose was shown (the schedule's choice)
  uint64_t age = 0;               // p
  uint64_t predicted = 0;         // frames the warp spans
  bool complete = true;           // the buffer had every row
  bool first_use = false;         // this eye shows visibility_frame for the first time
  std::optional<int64_t> visibility_age_ns;  // display time of this frame minus that of visibility_frame
  render::EyeStats stats;         // GPU pass times, warp counts
};

struct FrameRecord {
  uint64_t frame = 0;
  int64_t display_time_ns = 0;
  int64_t scene_time_ns = 0;  // the scene time displayed (FramePose::scene_time_ns)
  bool pose_reused = false;  // the source's pose was invalid: the last valid one was shown
  std::array<EyeFrameRecord, 2> eyes{};
  // Response time of a visibility frame first used in this frame (pose sent -> visibility complete).
  std::optional<double> response_ms;
};

// One JSON line per frame (both eyes) for --stats-jsonl.
std::string frame_record_json(const FrameRecord& record);

// Accumulates FrameRecords into the run's summary numbers.
class FrameSummary {
 public:
  void add(const FrameRecord& record);
  uint64_t frames() const { return frames_; }
  uint64_t frames_with_visibility() const { return frames_with_visibility_; }
  // Frames shaded with no server visibility in either eye but some pixels from the shadow maps (offline).
  uint64_t frames_local() const { return frames_local_; }
  uint64_t pixels_shadow_map() const { return pixels_shadow_map_; }  // filled from the shadow maps, both eyes
  uint64_t pixels_other_eye() const { return pixels_other_eye_; }    // filled from the other eye's buffer
  uint64_t pixels_older() const { return pixels_older_; }            // ... from this eye's previous buffer
  uint64_t pixels_neighbour() const { return pixels_neighbour_; }    // ... from a neighbour on the tangent plane
  double predicted_frac() const;  // known surface pixels / surface pixels, both eyes, all frames
  double unknown_frac() const;    // unknown surface pixels / surface pixels
  std::optional<double> response_ms_median() const { return median(response_ms_); }
  std::optional<double> age_median() const { return median(ages_); }
  std::optional<double> gbuffer_ms_median() const { return median(gbuffer_ms_); }
  std::optional<double> warp_ms_median() const { return median(warp_ms_); }
  std::optional<double> shading_ms_median() const { return median(shading_ms_); }
  std::optional<double> forward_ms_median() const { return median(forward_ms_); }
  std::optional<double> eye_gpu_ms_median() const { return median(total_ms_); }  // every pass of one eye
  // The shadow-map re-render of a moving scene, over the frames that re-rendered faces (std::nullopt: none did).
  std::optional<double> shadow_update_ms_median() const { return median(shadow_update_ms_); }
  uint64_t responses() const { return response_ms_.size(); }

  static std::optional<double> median(std::vector<double> values);

 private:
  uint64_t frames_ = 0;
  uint64_t frames_with_visibility_ = 0;
  uint64_t frames_local_ = 0;
  uint64_t pixels_shadow_map_ = 0;
  uint64_t pixels_other_eye_ = 0;
  uint64_t pixels_older_ = 0;
  uint64_t pixels_neighbour_ = 0;
  uint64_t surface_ = 0;
  uint64_t known_ = 0;
  uint64_t unknown_ = 0;
  std::vector<double> response_ms_;
  std::vector<double> ages_;
  std::vector<double> gbuffer_ms_;
  std::vector<double> warp_ms_;
  std::vector<double> shading_ms_;
  std::vector<double> forward_ms_;
  std::vector<double> total_ms_;
  std::vector<double> shadow_update_ms_;
};

}  // namespace dhr::client
