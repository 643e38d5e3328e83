// Importers for public head-motion datasets, format detection, and the file-level entry points.
// Frames and units of each dataset: docs/traces.md and ../shared/data/MANIFEST.md.
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <system_error>

#include "pose_trace_internal.hpp"

namespace dhr {

using namespace trace_detail;

namespace trace_detail {

glm::dvec3 unity_to_openxr_position(const glm::dvec3& p) { return {p.x, p.y, -p.z}; }

glm::dquat unity_to_openxr_rotation(double qx, double qy, double qz, double qw) {
  // A mirror keeps the rotation angle and maps the axis a to -S a (axes are pseudo-vectors).
  return glm::dquat(qw, -qx, -qy, qz);
}

namespace {

const std::vector<std::string> kGulRawColumns = {"timestamp", "x", "y", "z", "qx", "qy", "qz", "qw"};
const std::vector<std::string> kGulInterpColumns = {"timestamp", "x",  "y",  "z",     "qx",   "qy",
                                                    "qz",        "qw", "roll", "pitch", "yaw"};
const std::vector<std::string> kNasrabadiColumns = {"t", "qx", "qy", "qz", "qw", "vx", "vy", "vz"};

constexpr double kTicksPerSecond = 1.0e7;  // .NET ticks are 100 ns
constexpr double kNanosecondsPerSecond = 1.0e9;
// The viewport vector is printed with 5 significant digits; a real convention mismatch is tens of degrees.
constexpr double kViewportAgreementDegrees = 2.0;

std::string header_text(const std::vector<std::string>& columns) {
  std::string out;
  for (const std::string& c : columns) out += (out.empty() ? "" : ",") + c;
  return out;
}

bool fields_equal(const std::vector<std::string_view>& fields, const std::vector<std::string>& columns) {
  return std::equal(fields.begin(), fields.end(), columns.begin(), columns.end());
}

// Reads the first non-blank line as the header and checks it.
bool expect_header(LineReader& reader, const std::string& name, const std::vector<std::string>& columns,
                   const char* format_name, std::string* out_error) {
  TextLine line;
  while (reader.next(&line)) {
    if (is_blank(line.text)) continue;
    if (line.text.size() <= kMaxLineLength && fields_equal(split_fields(line.text), columns)) return true;
    *out_error = at_line(name, line.number,
                         "expected the " + std::string(format_name) + " header '" + header_text(columns) + "'");
    return false;
  }
  *out_error = name + ": empty file";
  return false;
}

bool all_numeric(const std::vector<std::string_view>& fields) {
  std::string ignored;
  double v = 0.0;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!parse_double_field(fields[i], i + 1, "", &v, &ignored)) return false;
  }
  return true;
}

}  // namespace

TraceReadResult read_gul2020(std::string_view text, const std::string& name, const TraceReadOptions& options,
                             bool interpolated) {
  TraceReadResult result;
  result.format = interpolated ? TraceFormat::kGul2020Interp : TraceFormat::kGul2020Raw;
  const std::vector<std::string>& columns = interpolated ? kGulInterpColumns : kGulRawColumns;
  LineReader reader(text);
  if (!expect_header(reader, name, columns, trace_format_name(result.format), &result.error)) return result;

  RowFormat format;
  format.columns = columns;
  std::optional<std::int64_t> first_ticks;
  format.parse_row = [&](const std::vector<std::string_view>& f, TraceSample* out, std::string* err) {
    if (interpolated) {
      double ns = 0.0;
      if (!parse_double_field(f[0], 1, columns[0], &ns, err)) return false;
      out->time = ns / kNanosecondsPerSecond;
    } else {
      // Ticks since year 1 need 60 bits: subtract in integers, then convert (a double would lose 12.8 us).
      std::int64_t ticks = 0;
      if (!parse_int64_field(f[0], 1, columns[0], &ticks, err)) return false;
      if (ticks < 0) {
        *err = "column 1 (timestamp): negative .NET tick count";
        return false;
      }
      if (!first_ticks) first_ticks = ticks;
      out->time = static_cast<double>(ticks - *first_ticks) / kTicksPerSecond;
    }
    double v[7];
    for (std::size_t i = 0; i < 7; ++i) {
      if (!parse_double_field(f[i + 1], i + 2, columns[i + 1], &v[i], err)) return false;
    }
    // The HoloLens app recorded in Unity's frame (+Z forward; docs/traces.md shows the evidence).
    out->head.position = unity_to_openxr_position({v[0], v[1], v[2]});
    out->head.orientation = unity_to_openxr_rotation(v[3], v[4], v[5], v[6]);
    // roll/pitch/yaw (interpolated files) are derived from the quaternion: not needed.
    return true;
  };
  PoseTrace trace;
  trace.comments.push_back(std::string("imported from ") + trace_format_name(result.format) +
                           " (Gul et al. 2020, HoloLens; research use, cite the paper)");
  result.error = read_rows(reader, name, format, options, &trace);
  if (!result.error.empty()) return result;
  if (trace.samples.empty()) {
    result.error = name + ": no data rows";
    return result;
  }
  result.trace = std::move(trace);
  return result;
}

TraceReadResult read_nasrabadi2019(std::string_view text, const std::string& name, const TraceReadOptions& options) {
  TraceReadResult result;
  result.format = TraceFormat::kNasrabadi2019;
  LineReader reader(text);

  RowFormat format;
  format.columns = kNasrabadiColumns;
  std::size_t disagreeing_rows = 0;
  double worst_degrees = 0.0;
  format.parse_row = [&](const std::vector<std::string_view>& f, TraceSample* out, std::string* err) {
    double v[8];
    for (std::size_t i = 0; i < 8; ++i) {
      if (!parse_double_field(f[i], i + 1, kNasrabadiColumns[i], &v[i], err)) return false;
    }
    out->time = v[0];
    out->head.position = glm::dvec3(0.0);  // 3-DoF: the placement decides where the head is
    out->head.orientation = unity_to_openxr_rotation(v[1], v[2], v[3], v[4]);
    // The viewport centre is Unity's forward R(q)(0,0,1) with y negated; in OpenXR terms that is
    // (f.x, -f.y, -f.z) for our forward f = R(q')(0,0,-1). Checks the conversion row by row.
    const glm::dvec3 viewport(v[5], v[6], v[7]);
    const double q_norm = std::sqrt(glm::dot(out->head.orientation, out->head.orientation));
    const double v_norm = glm::length(viewport);
    if (q_norm > 1e-12 && v_norm > 1e-12) {
      const glm::dvec3 fwd = (out->head.orientation / q_norm) * glm::dvec3(0.0, 0.0, -1.0);
      const double c = std::clamp(glm::dot(glm::dvec3(fwd.x, -fwd.y, -fwd.z), viewport / v_norm), -1.0, 1.0);
      const double degrees = std::acos(c) * 180.0 / std::numbers::pi;
      if (degrees > kViewportAgreementDegrees) {
        ++disagreeing_rows;
        worst_degrees = std::max(worst_degrees, degrees);
      }
    }
    return true;
  };
  PoseTrace trace;
  trace.comments.push_back("imported from nasrabadi2019 (Nasrabadi et al. 2019, 360-video 3-DoF; MIT): "
                           "position fixed at the origin");
  result.error = read_rows(reader, name, format, options, &trace);
  if (!result.error.empty()) return result;
  if (trace.samples.empty()) {
    result.error = name + ": no data rows";
    return result;
  }
  if (disagreeing_rows > 0) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.1f", worst_degrees);
    trace.warnings.push_back(name + ": " + std::to_string(disagreeing_rows) +
                             " rows have viewport vectors that disagree with their quaternions by up to " + buffer +
                             " degrees (expected the Unity-like convention)");
  }
  result.trace = std::move(trace);
  return result;
}

}  // namespace trace_detail

const char* trace_format_name(TraceFormat format) {
  switch (format) {
    case TraceFormat::kAuto: return "auto";
    case TraceFormat::kCanonical: return "canonical";
    case TraceFormat::kGul2020Raw: return "gul2020-raw";
    case TraceFormat::kGul2020Interp: return "gul2020-interp";
    case TraceFormat::kNasrabadi2019: return "nasrabadi2019";
  }
  return "unknown";
}

std::optional<TraceFormat> parse_trace_format(std::string_view name) {
  for (TraceFormat f : {TraceFormat::kAuto, TraceFormat::kCanonical, TraceFormat::kGul2020Raw,
                        TraceFormat::kGul2020Interp, TraceFormat::kNasrabadi2019}) {
    if (name == trace_format_name(f)) return f;
  }
  return std::nullopt;
}

std::optional<TraceFormat> detect_trace_format(std::string_view text, std::string* out_error) {
  LineReader reader(text);
  TextLine line;
  while (reader.next(&line)) {
    const std::string_view t = trim(line.text);
    if (t.empty()) continue;
    if (t.front() == '#') return TraceFormat::kCanonical;  // only our format has comment lines
    const std::vector<std::string_view> fields = split_fields(t);
    if (fields.front() == "t") return TraceFormat::kCanonical;
    if (fields_equal(fields, kGulRawColumns)) return TraceFormat::kGul2020Raw;
    if (fields_equal(fields, kGulInterpColumns)) return TraceFormat::kGul2020Interp;
    if (fields.size() == kNasrabadiColumns.size() && all_numeric(fields)) return TraceFormat::kNasrabadi2019;
    const std::string shown = t.size() > 80 ? std::string(t.substr(0, 80)) + "..." : std::string(t);
    *out_error = "cannot tell the trace format from line " + std::to_string(line.number) + " ('" + shown +
                 "'); name it: canonical, gul2020-raw, gul2020-interp or nasrabadi2019";
    return std::nullopt;
  }
  *out_error = "empty file";
  return std::nullopt;
}

TraceReadResult parse_pose_trace(std::string_view text, const std::string& name, TraceFormat format,
                                 const TraceReadOptions& options) {
  if (format == TraceFormat::kAuto) {
    std::string problem;
    const std::optional<TraceFormat> detected = detect_trace_format(text, &problem);
    if (!detected) {
      TraceReadResult result;
      result.error = name + ": " + problem;
      return result;
    }
    format = *detected;
  }
  switch (format) {
    case TraceFormat::kGul2020Raw: return read_gul2020(text, name, options, false);
    case TraceFormat::kGul2020Interp: return read_gul2020(text, name, options, true);
    case TraceFormat::kNasrabadi2019: return read_nasrabadi2019(text, name, options);
    case TraceFormat::kCanonical:
    case TraceFormat::kAuto: break;
  }
  return read_canonical(text, name, options);
}

TraceReadResult read_pose_trace(const std::string& path, TraceFormat format, const TraceReadOptions& options) {
  TraceReadResult result;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    result.error = path + ": " + (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
    return result;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) {
    result.error = path + ": " + ec.message();
    return result;
  }
  if (size > options.max_file_bytes) {
    result.error = path + ": " + std::to_string(size) + " bytes is more than the reader's limit of " +
                   std::to_string(options.max_file_bytes) + " bytes";
    return result;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    result.error = path + ": cannot open for reading";
    return result;
  }
  std::string text;
  text.reserve(static_cast<std::size_t>(size));
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) {
    result.error = path + ": read failed";
    return result;
  }
  if (text.size() > options.max_file_bytes) {  // grew while being read (a recording in progress)
    result.error = path + ": grew past the reader's limit of " + std::to_string(options.max_file_bytes) +
                   " bytes while being read";
    return result;
  }
  return parse_pose_trace(text, path, format, options);
}

}  // namespace dhr
