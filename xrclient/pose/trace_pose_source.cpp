#include "pose/trace_pose_source.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace dhr::client {

TracePoseSource::TracePoseSource(PoseTrace trace, const EyeModel& eyes, const TracePlacement& placement,
                                 std::string name, int64_t frame_period_ns)
    : trace_(std::move(trace)), eyes_(eyes), name_(std::move(name)), period_ns_(frame_period_ns) {
  if (trace_.empty()) throw std::invalid_argument("TracePoseSource: empty trace");
  if (period_ns_ <= 0) throw std::invalid_argument("TracePoseSource: frame period must be positive");
  T_scene_trace_ = placement_transform(placement, trace_.samples.front().head);
}

PoseTrace TracePoseSource::load(const std::string& path) {
  TraceReadResult result = read_pose_trace(path);
  if (!result) throw std::runtime_error(result.error);
  if (result.trace->empty()) throw std::runtime_error(path + ": the trace has no samples");
  return std::move(*result.trace);
}

uint64_t TracePoseSource::frame_count() const {
  const double period_s = static_cast<double>(period_ns_) * 1e-9;
  return static_cast<uint64_t>(std::floor(trace_.duration() / period_s + 1e-9)) + 1;
}

bool TracePoseSource::next(FramePose& out) {
  if (next_frame_ >= frame_count()) return false;
  const int64_t t_ns = static_cast<int64_t>(next_frame_) * period_ns_;
  const TraceSample sample = trace_.sample(trace_.start_time() + static_cast<double>(t_ns) * 1e-9);
  out.frame = next_frame_;
  out.display_time_ns = t_ns;
  out.scene_time_ns = t_ns;
  out.views = trace_views(trace_, sample, eyes_, T_scene_trace_);
  ++next_frame_;
  return true;
}

std::string TracePoseSource::describe() const {
  char text[96];
  std::snprintf(text, sizeof(text), " (%.1f s, %zu samples)", trace_.duration(), trace_.samples.size());
  return "trace " + name_ + text;
}

}  // namespace dhr::client
