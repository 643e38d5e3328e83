// The row loop and field parsing shared by every trace format (see pose_trace_internal.hpp).
#include <glm/geometric.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>
#include <type_traits>

#include "pose_trace_internal.hpp"

namespace dhr::trace_detail {

bool LineReader::next(TextLine* out_line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  std::string_view line;
  if (end == std::string_view::npos) {
    line = text_.substr(pos_);
    pos_ = text_.size();
    out_line->terminated = false;
  } else {
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    out_line->terminated = true;
  }
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // files written on Windows
  out_line->text = line;
  out_line->number = ++number_;
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool is_blank(std::string_view s) { return trim(s).empty(); }

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(line.substr(start)));
      return fields;
    }
    fields.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

std::string at_line(const std::string& name, std::size_t line, const std::string& message) {
  return name + ":" + std::to_string(line) + ": " + message;
}

namespace {

// Field text for messages: quoted, shortened when long.
std::string quoted(std::string_view field) {
  if (field.size() > 40) return "'" + std::string(field.substr(0, 40)) + "...'";
  return "'" + std::string(field) + "'";
}

std::string column_label(std::size_t column, std::string_view column_name) {
  return "column " + std::to_string(column) + " (" + std::string(column_name) + ")";
}

template <typename T>
bool parse_number(std::string_view field, std::size_t column, std::string_view column_name, T* out_value,
                  std::string* out_error) {
  std::string_view digits = field;
  // from_chars rejects a leading '+', which other tools write.
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+') digits.remove_prefix(1);
  T value{};
  const char* first = digits.data();
  const char* last = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (field.empty()) {
    *out_error = column_label(column, column_name) + ": empty value";
    return false;
  }
  if (ec == std::errc::result_out_of_range) {
    *out_error = column_label(column, column_name) + ": " + quoted(field) + " is out of range";
    return false;
  }
  if (ec != std::errc() || ptr != last) {
    *out_error = column_label(column, column_name) + ": " + quoted(field) + " is not a number";
    return false;
  }
  if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(value)) {
      *out_error = column_label(column, column_name) + ": non-finite value " + quoted(field);
      return false;
    }
  }
  *out_value = value;
  return true;
}

}  // namespace

bool parse_double_field(std::string_view field, std::size_t column, std::string_view column_name, double* out_value,
                        std::string* out_error) {
  return parse_number(field, column, column_name, out_value, out_error);
}

bool parse_float_field(std::string_view field, std::size_t column, std::string_view column_name, float* out_value,
                       std::string* out_error) {
  return parse_number(field, column, column_name, out_value, out_error);
}

bool parse_int64_field(std::string_view field, std::size_t column, std::string_view column_name,
                       std::int64_t* out_value, std::string* out_error) {
  return parse_number(field, column, column_name, out_value, out_error);
}

std::string format_double(double v) {
  char buffer[64];
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  if (ec != std::errc()) return "nan";  // cannot happen for 64 bytes; the reader would reject it
  return std::string(buffer, ptr);
}

std::string format_float(float v) {
  char buffer[64];
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  if (ec != std::errc()) return "nan";
  return std::string(buffer, ptr);
}

namespace {

std::string number(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

bool finite_quat(const glm::dquat& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}

bool finite_vec(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string check_pose(Pose* pose, const char* what, double* io_max_deviation) {
  if (!finite_vec(pose->position)) return std::string(what) + " position is not finite";
  if (!finite_quat(pose->orientation)) return std::string(what) + " orientation is not finite";
  const double norm = std::sqrt(glm::dot(pose->orientation, pose->orientation));
  if (!(norm > 1e-12)) return std::string(what) + " orientation is a zero quaternion";
  if (norm < kMinQuatNorm || norm > kMaxQuatNorm) {
    return std::string(what) + " quaternion norm " + number(norm) + " is too far from 1 to be a rotation";
  }
  // Already unit to rounding: left bit-exact, so that write -> read round trips are exact.
  if (std::fabs(norm - 1.0) > 1e-14) pose->orientation = pose->orientation / norm;
  *io_max_deviation = std::max(*io_max_deviation, std::fabs(norm - 1.0));
  const double distance = glm::length(pose->position);
  if (distance > kMaxPositionMetres) {
    return std::string(what) + " position is " + number(distance) + " m from the origin (limit " +
           number(kMaxPositionMetres) + " m)";
  }
  return {};
}

}  // namespace

std::string check_and_normalize(TraceSample* sample, bool with_eye_poses, bool with_fov,
                                double* out_max_norm_deviation) {
  *out_max_norm_deviation = 0.0;
  if (!std::isfinite(sample->time)) return "time is not finite";
  std::string problem = check_pose(&sample->head, "head", out_max_norm_deviation);
  if (!problem.empty()) return problem;
  static const char* const kEyeNames[2] = {"left eye", "right eye"};
  if (with_eye_poses) {
    for (int i = 0; i < 2; ++i) {
      problem = check_pose(&sample->eye[i], kEyeNames[i], out_max_norm_deviation);
      if (!problem.empty()) return problem;
    }
  }
  if (with_fov) {
    for (int i = 0; i < 2; ++i) {
      if (auto fov_problem = validate_fov(sample->fov[i])) return std::string(kEyeNames[i]) + ": " + *fov_problem;
    }
  }
  return {};
}

std::vector<std::string> canonical_columns(bool with_eye_poses, bool with_fov) {
  std::vector<std::string> columns = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
  if (with_eye_poses) {
    for (const char* eye : {"l", "r"}) {
      for (const char* c : {"x", "y", "z", "qx", "qy", "qz", "qw"}) columns.push_back(std::string(eye) + c);
    }
  }
  if (with_fov) {
    for (const char* eye : {"l", "r"}) {
      for (const char* c : {"fov_left", "fov_right", "fov_up", "fov_down"}) columns.push_back(std::string(eye) + c);
    }
  }
  return columns;
}

std::string read_rows(LineReader& reader, const std::string& name, const RowFormat& format,
                      const TraceReadOptions& options, PoseTrace* trace) {
  std::size_t off_norm_rows = 0;
  double worst_deviation = 0.0;
  TextLine line;
  while (reader.next(&line)) {
    if (line.text.size() > kMaxLineLength) {
      return at_line(name, line.number, "line is longer than " + std::to_string(kMaxLineLength) + " characters");
    }
    if (is_blank(line.text)) continue;
    const std::string_view trimmed = trim(line.text);
    if (format.allow_comments && trimmed.front() == '#') {
      trace->comments.emplace_back(trim(trimmed.substr(1)));
      continue;
    }

    std::string problem;
    TraceSample sample;
    double deviation = 0.0;
    const std::vector<std::string_view> fields = split_fields(line.text);
    if (fields.size() != format.columns.size()) {
      problem = "expected " + std::to_string(format.columns.size()) + " columns, got " + std::to_string(fields.size());
    } else if (!format.parse_row(fields, &sample, &problem)) {
      if (problem.empty()) problem = "unreadable row";
    } else {
      problem = check_and_normalize(&sample, format.has_eye_poses, format.has_fov, &deviation);
      if (problem.empty() && !trace->samples.empty() && sample.time < trace->samples.back().time) {
        problem = "time goes backwards (" + number(sample.time) + " s after " + number(trace->samples.back().time) +
                  " s on the previous row)";
      }
    }
    if (!line.terminated) {
      // A final line without a line end is where a recording stops when it is interrupted; a value cut
      // short there (qw = 0.9 instead of 0.99...) still parses, so a clearly non-unit quaternion counts too.
      if (problem.empty() && deviation > kTruncatedNormDeviation) {
        problem = "quaternion norm is off from 1 by " + number(deviation);
      }
      if (!problem.empty()) {
        trace->warnings.push_back(at_line(name, line.number,
                                          "the last line has no line end and is incomplete (" + problem +
                                              "): dropped it, as left by an interrupted recording"));
        break;
      }
    }
    if (!problem.empty()) return at_line(name, line.number, problem);
    if (trace->samples.size() >= options.max_rows) {
      return at_line(name, line.number,
                     "more than " + std::to_string(options.max_rows) + " data rows (the reader's max_rows limit)");
    }
    if (deviation > kWarnNormDeviation) {
      ++off_norm_rows;
      worst_deviation = std::max(worst_deviation, deviation);
    }
    trace->samples.push_back(sample);
  }
  if (off_norm_rows > 0) {
    trace->warnings.push_back(name + ": " + std::to_string(off_norm_rows) + " rows had quaternion norms off from 1 by " +
                              "up to " + number(worst_deviation) + "; renormalized");
  }
  return {};
}

}  // namespace dhr::trace_detail
