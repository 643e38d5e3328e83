// Pieces shared by the pose-trace readers and writers (pose_trace_*.cpp); not a public interface.
#pragma once
#include "traces/pose_trace.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace dhr::trace_detail {

inline constexpr std::size_t kMaxLineLength = 4096;
// Quaternions whose norm is outside [kMinQuatNorm, kMaxQuatNorm] are not rotations that lost a little
// precision but garbage; within, they are renormalized.
inline constexpr double kMinQuatNorm = 0.5;
inline constexpr double kMaxQuatNorm = 2.0;
// Norm deviation that marks an unterminated final line as cut short (digits missing), and the smaller
// one that is worth a warning (the datasets' own rounding stays below 1e-5).
inline constexpr double kTruncatedNormDeviation = 1e-2;
inline constexpr double kWarnNormDeviation = 1e-3;

// One physical line (without its line end and any '\r').
struct TextLine {
  std::string_view text;
  std::size_t number = 0;   // 1-based
  bool terminated = false;  // followed by '\n'
};

// Iterates the lines of a text in order.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  bool next(TextLine* out_line);

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

std::string_view trim(std::string_view s);
bool is_blank(std::string_view s);
// Splits on ',' and trims spaces/tabs around each field (the gul2020 raw files use ", ").
std::vector<std::string_view> split_fields(std::string_view line);

// "<name>:<line>: <message>"
std::string at_line(const std::string& name, std::size_t line, const std::string& message);

// Field parsers; column is 1-based, for messages like "column 3 (y): 'abc' is not a number".
bool parse_double_field(std::string_view field, std::size_t column, std::string_view column_name, double* out_value,
                        std::string* out_error);
bool parse_float_field(std::string_view field, std::size_t column, std::string_view column_name, float* out_value,
                       std::string* out_error);
bool parse_int64_field(std::string_view field, std::size_t column, std::string_view column_name,
                       std::int64_t* out_value, std::string* out_error);

// Shortest text that reads back to exactly the same double.
std::string format_double(double v);
std::string format_float(float v);

// Checks a sample's values and renormalizes its quaternions. out_max_norm_deviation gets the largest
// |1 - |q|| seen (before renormalization). Returns the problem, or an empty string when usable.
std::string check_and_normalize(TraceSample* sample, bool with_eye_poses, bool with_fov,
                                double* out_max_norm_deviation);

// Column names of the canonical layout for the chosen optional columns.
std::vector<std::string> canonical_columns(bool with_eye_poses, bool with_fov);

// How one format's data rows look and turn into samples (canonical frame, not yet validated).
struct RowFormat {
  std::vector<std::string> columns;  // names, for messages; the count is what every row must have
  bool has_eye_poses = false;
  bool has_fov = false;
  bool allow_comments = false;  // '#' lines between rows are comments (canonical only)
  std::function<bool(const std::vector<std::string_view>& fields, TraceSample* out_sample, std::string* out_error)>
      parse_row;
};

// The loop every format shares, from `reader`'s current position: blank lines, line length, column count,
// parsing, validation, time order, row limit and the final-line policy (see read_pose_trace). Appends to
// trace->samples/warnings; returns "<name>:<line>: <problem>" or an empty string.
std::string read_rows(LineReader& reader, const std::string& name, const RowFormat& format,
                      const TraceReadOptions& options, PoseTrace* trace);

// Per-format readers (text already in memory). They fill result.trace or result.error.
TraceReadResult read_canonical(std::string_view text, const std::string& name, const TraceReadOptions& options);
TraceReadResult read_gul2020(std::string_view text, const std::string& name, const TraceReadOptions& options,
                             bool interpolated);
TraceReadResult read_nasrabadi2019(std::string_view text, const std::string& name, const TraceReadOptions& options);

// Unity's frame (left-handed, +Y up, +Z forward, +X right) -> OpenXR's (right-handed, -Z forward): the
// mirror S = diag(1, 1, -1). Positions flip z; a rotation R becomes S R S, i.e. quaternion
// (x, y, z, w) -> (-x, -y, z, w).
glm::dvec3 unity_to_openxr_position(const glm::dvec3& p);
glm::dquat unity_to_openxr_rotation(double qx, double qy, double qz, double qw);

}  // namespace dhr::trace_detail
