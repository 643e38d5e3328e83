// Fuzz target: parse_pose_trace on arbitrary text, once with format detection and once forcing one of
// the four formats (chosen by the input length, so every format sees every kind of text).
// Properties: no crash, hang or sanitizer report; a failure carries an error; a parsed trace keeps the
// promises of pose_trace.hpp (non-decreasing finite times, unit quaternions, finite positions, valid
// FOVs when present, row limit); sampling it gives finite unit-quaternion poses; and its canonical CSV
// reads back to the same trace (times, positions and FOVs exactly, quaternions to 1e-12: the reader
// divides by the norm again).
#include "traces/pose_trace.hpp"
#include "fuzz_support.hpp"

#include <cmath>
#include <limits>
#include <string_view>

namespace {

constexpr size_t kMaxRows = 5000;

bool unit(const glm::dquat& q) {
  const double n = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return std::isfinite(n) && std::fabs(n - 1.0) < 1e-9;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool close(const glm::dquat& a, const glm::dquat& b) {
  return std::fabs(a.w - b.w) <= 1e-12 && std::fabs(a.x - b.x) <= 1e-12 && std::fabs(a.y - b.y) <= 1e-12 &&
         std::fabs(a.z - b.z) <= 1e-12;
}

bool same_fov(const dhr::Fov& a, const dhr::Fov& b) {
  return a.angle_left == b.angle_left && a.angle_right == b.angle_right && a.angle_up == b.angle_up &&
         a.angle_down == b.angle_down;
}

void check_trace(const dhr::PoseTrace& trace) {
  DHR_FUZZ_CHECK(trace.samples.size() <= kMaxRows);
  double previous = -std::numeric_limits<double>::infinity();
  for (const dhr::TraceSample& s : trace.samples) {
    DHR_FUZZ_CHECK_MSG(std::isfinite(s.time) && s.time >= previous, "times not finite and non-decreasing");
    previous = s.time;
    DHR_FUZZ_CHECK_MSG(finite(s.head.position) && unit(s.head.orientation), "bad head pose");
    if (trace.has_eye_poses)
      for (const dhr::Pose& eye : s.eye) DHR_FUZZ_CHECK_MSG(finite(eye.position) && unit(eye.orientation), "bad eye");
    if (trace.has_fov)
      for (const dhr::Fov& fov : s.fov) DHR_FUZZ_CHECK_MSG(!dhr::validate_fov(fov), "bad FOV");
  }
  if (trace.empty()) return;
  for (double f : {0.0, 0.37, 0.5, 1.0}) {
    const dhr::TraceSample s = trace.sample(trace.start_time() + f * trace.duration());
    DHR_FUZZ_CHECK_MSG(finite(s.head.position) && unit(s.head.orientation), "bad sampled pose");
  }

  // Canonical CSV and back.
  const std::string text = dhr::format_canonical_trace(trace);
  dhr::TraceReadOptions options;
  options.max_rows = kMaxRows;
  const dhr::TraceReadResult back = dhr::parse_pose_trace(text, "canonical", dhr::TraceFormat::kCanonical, options);
  DHR_FUZZ_CHECK_MSG(back.ok(), back.error.c_str());
  const dhr::PoseTrace& t = *back.trace;
  DHR_FUZZ_CHECK(t.samples.size() == trace.samples.size());
  DHR_FUZZ_CHECK(t.has_eye_poses == trace.has_eye_poses && t.has_fov == trace.has_fov);
  for (size_t i = 0; i < t.samples.size(); ++i) {
    const dhr::TraceSample &a = trace.samples[i], &b = t.samples[i];
    DHR_FUZZ_CHECK_MSG(a.time == b.time && a.head.position == b.head.position, "canonical round trip differs");
    DHR_FUZZ_CHECK_MSG(close(a.head.orientation, b.head.orientation), "canonical round trip differs");
    for (int e = 0; e < 2 && trace.has_eye_poses; ++e)
      DHR_FUZZ_CHECK_MSG(a.eye[e].position == b.eye[e].position && close(a.eye[e].orientation, b.eye[e].orientation),
                         "canonical round trip differs (eye)");
    for (int e = 0; e < 2 && trace.has_fov; ++e)
      DHR_FUZZ_CHECK_MSG(same_fov(a.fov[e], b.fov[e]), "canonical round trip differs (FOV)");
  }
}

void parse_and_check(std::string_view text, dhr::TraceFormat format) {
  dhr::TraceReadOptions options;
  options.max_rows = kMaxRows;
  const dhr::TraceReadResult result = dhr::parse_pose_trace(text, "fuzz.csv", format, options);
  if (!result.ok()) {
    DHR_FUZZ_CHECK_MSG(!result.error.empty(), "failure without an error message");
    return;
  }
  DHR_FUZZ_CHECK(result.format != dhr::TraceFormat::kAuto);
  check_trace(*result.trace);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  parse_and_check(text, dhr::TraceFormat::kAuto);
  static constexpr dhr::TraceFormat kForced[4] = {dhr::TraceFormat::kCanonical, dhr::TraceFormat::kGul2020Raw,
                                                  dhr::TraceFormat::kGul2020Interp, dhr::TraceFormat::kNasrabadi2019};
  parse_and_check(text, kForced[size % 4]);
  return 0;
}
