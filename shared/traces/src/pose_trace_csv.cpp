// The canonical dhr-trace CSV: reader, writer and streaming writer (format in docs/traces.md).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "pose_trace_internal.hpp"

namespace dhr {

using namespace trace_detail;

namespace {

constexpr std::string_view kMagic = "dhr-trace";
constexpr std::string_view kVersion = "v1";

std::string join(const std::vector<std::string>& columns) {
  std::string out;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) out += ',';
    out += columns[i];
  }
  return out;
}

bool header_matches(const std::vector<std::string_view>& fields, const std::vector<std::string>& columns) {
  if (fields.size() != columns.size()) return false;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (fields[i] != columns[i]) return false;
  }
  return true;
}

// Columns 0..7 are t, head position, head quaternion (x, y, z, w); eye poses and FOVs follow.
bool parse_canonical_row(const std::vector<std::string_view>& f, const std::vector<std::string>& names,
                         bool with_eye_poses, bool with_fov, TraceSample* out, std::string* out_error) {
  std::size_t i = 0;
  auto next_double = [&](double* v) {
    const bool ok = parse_double_field(f[i], i + 1, names[i], v, out_error);
    ++i;
    return ok;
  };
  auto next_pose = [&](Pose* p) {
    return next_double(&p->position.x) && next_double(&p->position.y) && next_double(&p->position.z) &&
           next_double(&p->orientation.x) && next_double(&p->orientation.y) && next_double(&p->orientation.z) &&
           next_double(&p->orientation.w);
  };
  if (!next_double(&out->time) || !next_pose(&out->head)) return false;
  if (with_eye_poses && (!next_pose(&out->eye[0]) || !next_pose(&out->eye[1]))) return false;
  if (with_fov) {
    for (Fov& fov : out->fov) {
      for (float* angle : {&fov.angle_left, &fov.angle_right, &fov.angle_up, &fov.angle_down}) {
        if (!parse_float_field(f[i], i + 1, names[i], angle, out_error)) return false;
        ++i;
      }
    }
  }
  return true;
}

void append_pose(std::string* row, const Pose& p) {
  for (double v : {p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
                   p.orientation.w}) {
    *row += ',';
    *row += format_double(v);
  }
}

std::string format_header(bool with_eye_poses, bool with_fov, const std::vector<std::string>& comments) {
  std::string out = "# " + std::string(kMagic) + " " + std::string(kVersion) + "\n";
  for (const std::string& comment : comments) {
    std::string line = comment;
    for (char& c : line) {
      if (c == '\n' || c == '\r') c = ' ';  // one comment, one line
    }
    out += "# " + line + "\n";
  }
  out += join(canonical_columns(with_eye_poses, with_fov)) + "\n";
  return out;
}

std::string format_row(const TraceSample& s, bool with_eye_poses, bool with_fov) {
  std::string row = format_double(s.time);
  append_pose(&row, s.head);
  if (with_eye_poses) {
    append_pose(&row, s.eye[0]);
    append_pose(&row, s.eye[1]);
  }
  if (with_fov) {
    for (const Fov& fov : s.fov) {
      for (float angle : {fov.angle_left, fov.angle_right, fov.angle_up, fov.angle_down}) {
        row += ',';
        row += format_float(angle);
      }
    }
  }
  row += '\n';
  return row;
}

std::string io_error(const std::string& path, const char* what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

}  // namespace

namespace trace_detail {

TraceReadResult read_canonical(std::string_view text, const std::string& name, const TraceReadOptions& options) {
  TraceReadResult result;
  result.format = TraceFormat::kCanonical;
  PoseTrace trace;
  LineReader reader(text);
  TextLine line;
  bool have_header = false;
  bool first_line = true;  // only the first non-blank line can be the "# dhr-trace <version>" line
  while (!have_header && reader.next(&line)) {
    if (line.text.size() > kMaxLineLength) {
      result.error = at_line(name, line.number, "line is longer than " + std::to_string(kMaxLineLength) + " characters");
      return result;
    }
    const std::string_view t = trim(line.text);
    if (t.empty()) continue;
    const bool may_be_version = first_line;
    first_line = false;
    if (t.front() == '#') {
      const std::string_view body = trim(t.substr(1));
      // Later comments are free text even when they start with the magic word: the writer puts the version
      // line first and copies comments verbatim after it, so a written trace always reads back.
      if (may_be_version && body.substr(0, kMagic.size()) == kMagic) {
        const std::string_view version = trim(body.substr(kMagic.size()));
        if (version != kVersion) {
          result.error = at_line(name, line.number,
                                 "unsupported trace version '" + std::string(version) + "' (this reader knows '" +
                                     std::string(kMagic) + " " + std::string(kVersion) + "')");
          return result;
        }
      } else {
        trace.comments.emplace_back(body);
      }
      continue;
    }
    const std::vector<std::string_view> fields = split_fields(line.text);
    bool matched = false;
    for (bool eyes : {false, true}) {
      for (bool fov : {false, true}) {
        if (!matched && header_matches(fields, canonical_columns(eyes, fov))) {
          trace.has_eye_poses = eyes;
          trace.has_fov = fov;
          matched = true;
        }
      }
    }
    if (!matched) {
      result.error = at_line(name, line.number,
                             "not a dhr-trace column header: expected '" + join(canonical_columns(false, false)) +
                                 "', optionally followed by the eye pose columns 'lx,...,rqw' and/or the FOV "
                                 "columns 'lfov_left,...,rfov_down' (docs/traces.md)");
      return result;
    }
    have_header = true;
  }
  if (!have_header) {
    result.error = name + ": no column header (empty file?)";
    return result;
  }

  RowFormat format;
  format.columns = canonical_columns(trace.has_eye_poses, trace.has_fov);
  format.has_eye_poses = trace.has_eye_poses;
  format.has_fov = trace.has_fov;
  format.allow_comments = true;
  format.parse_row = [&format](const std::vector<std::string_view>& f, TraceSample* out, std::string* err) {
    return parse_canonical_row(f, format.columns, format.has_eye_poses, format.has_fov, out, err);
  };
  result.error = read_rows(reader, name, format, options, &trace);
  if (!result.error.empty()) return result;
  if (trace.samples.empty()) {
    result.error = name + ": no data rows";
    return result;
  }
  result.trace = std::move(trace);
  return result;
}

}  // namespace trace_detail

std::string format_canonical_trace(const PoseTrace& trace) {
  std::string out = format_header(trace.has_eye_poses, trace.has_fov, trace.comments);
  for (const TraceSample& s : trace.samples) out += format_row(s, trace.has_eye_poses, trace.has_fov);
  return out;
}

bool write_pose_trace(const std::string& path, const PoseTrace& trace, std::string* out_error) {
  const std::string text = format_canonical_trace(trace);
  // Written beside the target and renamed, so a failed write never leaves a half file under the name.
  const std::string temp = path + ".tmp";
  std::FILE* file = std::fopen(temp.c_str(), "wb");
  if (file == nullptr) {
    *out_error = io_error(temp, "cannot create");
    return false;
  }
  const bool wrote = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  int error_number = errno;
  const bool closed = std::fclose(file) == 0;
  if (wrote && !closed) error_number = errno;
  if (!wrote || !closed) {
    errno = error_number;
    *out_error = io_error(temp, "write failed");
    std::remove(temp.c_str());
    return false;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    *out_error = io_error(path, "cannot rename the temporary file into place");
    std::remove(temp.c_str());
    return false;
  }
  return true;
}

PoseTraceWriter::~PoseTraceWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

bool PoseTraceWriter::open(const std::string& path, bool with_eye_poses, bool with_fov,
                           const std::vector<std::string>& comments, std::string* out_error) {
  if (file_ != nullptr) {
    *out_error = path_ + ": already open";
    return false;
  }
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) {
    *out_error = io_error(path, "cannot create");
    return false;
  }
  path_ = path;
  with_eye_poses_ = with_eye_poses;
  with_fov_ = with_fov;
  rows_ = 0;
  const std::string header = format_header(with_eye_poses, with_fov, comments);
  if (std::fputs(header.c_str(), file_) < 0 || std::fflush(file_) != 0) {
    *out_error = io_error(path, "write failed");
    std::fclose(file_);
    file_ = nullptr;
    return false;
  }
  return true;
}

bool PoseTraceWriter::append(const TraceSample& sample, std::string* out_error) {
  if (file_ == nullptr) {
    *out_error = "pose trace writer: not open";
    return false;
  }
  TraceSample s = sample;
  double deviation = 0.0;
  std::string problem = check_and_normalize(&s, with_eye_poses_, with_fov_, &deviation);
  if (problem.empty() && rows_ > 0 && s.time < last_time_) problem = "time goes backwards";
  if (!problem.empty()) {
    *out_error = path_ + ": row " + std::to_string(rows_ + 1) + " rejected: " + problem;
    return false;
  }
  const std::string row = format_row(s, with_eye_poses_, with_fov_);
  if (std::fputs(row.c_str(), file_) < 0 || std::fflush(file_) != 0) {
    *out_error = io_error(path_, "write failed");
    return false;
  }
  last_time_ = s.time;
  ++rows_;
  return true;
}

bool PoseTraceWriter::close(std::string* out_error) {
  if (file_ == nullptr) return true;
  const bool ok = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok) {
    *out_error = io_error(path_, "close failed");
    return false;
  }
  return true;
}

}  // namespace dhr
