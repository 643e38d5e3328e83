// Head-pose traces: recorded head (and optionally per-eye) poses over time, in the OpenXR frame
// (right-handed, +Y up, -Z forward, metres, seconds). The project's canonical CSV format, importers for
// public datasets, sampling (lerp + shortest-path slerp) and resampling. docs/traces.md documents the
// format, the datasets' frames and how they are mapped.
#pragma once
#include "math/pose.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dhr {

// One moment of a trace. eye[]/fov[] are meaningful only when the trace says it has them
// (PoseTrace::has_eye_poses / has_fov). Index 0 is the left eye, 1 the right (OpenXR's view order).
struct TraceSample {
  double time = 0.0;  // seconds, in the trace's own time base
  Pose head;          // T_trace_head
  std::array<Pose, 2> eye{};
  std::array<Fov, 2> fov{};
};

struct PoseTrace {
  std::vector<TraceSample> samples;  // time non-decreasing, unit quaternions, finite values
  bool has_eye_poses = false;
  bool has_fov = false;
  std::vector<std::string> comments;  // free-text '#' lines (provenance), without the leading "# "
  std::vector<std::string> warnings;  // what the reader tolerated (dropped final line, renormalizations)

  bool empty() const { return samples.empty(); }
  double start_time() const { return samples.empty() ? 0.0 : samples.front().time; }
  double end_time() const { return samples.empty() ? 0.0 : samples.back().time; }
  double duration() const { return end_time() - start_time(); }

  // The pose at time t (trace time base): position (and FOV angles) linearly interpolated, orientation
  // by shortest-path slerp; clamped to the first/last sample outside the trace. Requires !empty().
  TraceSample sample(double t) const;
};

// Samples at start_time + i / rate_hz for every i with that time <= end_time (times computed by
// multiplication, not accumulation); requires rate_hz > 0 and a non-empty trace.
PoseTrace resample_trace(const PoseTrace& trace, double rate_hz);
// Keeps the samples with time - start_time <= max_seconds (max_seconds >= 0).
PoseTrace truncate_trace(const PoseTrace& trace, double max_seconds);

// Spherical linear interpolation along the shorter arc (q and -q are the same rotation); a, b unit.
glm::dquat slerp_shortest(const glm::dquat& a, const glm::dquat& b, double s);

enum class TraceFormat {
  kAuto,           // detected from the first line (see detect_trace_format)
  kCanonical,      // this project's CSV (docs/traces.md)
  kGul2020Raw,     // Gül et al. 2020 HoloLens raw: .NET ticks, ", " separator, Unity frame
  kGul2020Interp,  // same, interpolated to 200 Hz: ns from start, extra roll/pitch/yaw columns
  kNasrabadi2019,  // Nasrabadi et al. 2019 360-video 3-DoF: no header, seconds, Unity-like frame
};

// "auto", "canonical", "gul2020-raw", "gul2020-interp", "nasrabadi2019".
const char* trace_format_name(TraceFormat format);
std::optional<TraceFormat> parse_trace_format(std::string_view name);

struct TraceReadOptions {
  std::uint64_t max_file_bytes = 512ull << 20;  // larger files are refused before reading
  std::size_t max_rows = 10'000'000;            // more data rows is an error
};

struct TraceReadResult {
  std::optional<PoseTrace> trace;
  TraceFormat format = TraceFormat::kAuto;  // the format actually parsed (after detection)
  std::string error;                        // "<file>:<line>: <problem>" (or "<file>: <problem>")

  bool ok() const { return trace.has_value(); }
  explicit operator bool() const { return ok(); }
};

// Reads a trace file in the given format (or detects it). Never throws. Bad rows are rejected with the
// file name and line number; a final line without a line end that is incomplete (wrong column count,
// unparsable, or a quaternion norm off by more than 1%) is dropped with a warning instead, as it is
// what an interrupted recording leaves behind. Blank lines are skipped.
TraceReadResult read_pose_trace(const std::string& path, TraceFormat format = TraceFormat::kAuto,
                                const TraceReadOptions& options = {});
// The same from text in memory; `name` stands for the file in messages.
TraceReadResult parse_pose_trace(std::string_view text, const std::string& name,
                                 TraceFormat format = TraceFormat::kAuto, const TraceReadOptions& options = {});

// Guesses the format from the first non-blank line: "# dhr-trace" or a "t,x,y,..." header -> canonical;
// "timestamp,x,y,z,qx,qy,qz,qw" -> gul2020-raw; the same plus roll,pitch,yaw -> gul2020-interp; eight
// numbers and no header -> nasrabadi2019. std::nullopt with the reason in out_error otherwise.
std::optional<TraceFormat> detect_trace_format(std::string_view text, std::string* out_error);

// Canonical CSV text of a trace (header, comments, one row per sample; numbers in the shortest form that
// reads back to the same double, so write -> read is exact).
std::string format_canonical_trace(const PoseTrace& trace);
// Writes the canonical CSV to path (through a temporary file renamed into place). False with
// "<path>: <problem>" in out_error on failure.
bool write_pose_trace(const std::string& path, const PoseTrace& trace, std::string* out_error);

// Streams canonical rows to a file as they come, for recording a live session (--record-trace).
// Each row is flushed, so a crash leaves at most one partial final line (which the reader drops).
class PoseTraceWriter {
 public:
  PoseTraceWriter() = default;
  ~PoseTraceWriter();
  PoseTraceWriter(const PoseTraceWriter&) = delete;
  PoseTraceWriter& operator=(const PoseTraceWriter&) = delete;

  // Creates/truncates path and writes the header for the chosen optional columns.
  bool open(const std::string& path, bool with_eye_poses, bool with_fov, const std::vector<std::string>& comments,
            std::string* out_error);
  // Appends one row. Rejects what the reader would reject: non-finite values, zero quaternions, absurd
  // positions, invalid FOVs, time going backwards.
  bool append(const TraceSample& sample, std::string* out_error);
  bool close(std::string* out_error);
  bool is_open() const { return file_ != nullptr; }
  std::size_t rows() const { return rows_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  bool with_eye_poses_ = false;
  bool with_fov_ = false;
  std::size_t rows_ = 0;
  double last_time_ = 0.0;
};

}  // namespace dhr
