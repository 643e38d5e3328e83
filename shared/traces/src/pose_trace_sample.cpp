// Sampling a trace between its rows: linear position, shortest-path slerp orientation, clamped ends.
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "traces/pose_trace.hpp"

namespace dhr {

namespace {

// Resampled traces beyond this are a caller mistake (10 hours at 1 kHz), not a wish.
constexpr double kMaxResampledRows = 36.0e6;

Pose interpolate_pose(const Pose& a, const Pose& b, double s) {
  Pose out;
  out.position = a.position + (b.position - a.position) * s;
  out.orientation = slerp_shortest(a.orientation, b.orientation, s);
  return out;
}

float lerp_angle(float a, float b, double s) {
  return static_cast<float>(static_cast<double>(a) + (static_cast<double>(b) - static_cast<double>(a)) * s);
}

Fov interpolate_fov(const Fov& a, const Fov& b, double s) {
  Fov out;
  out.angle_left = lerp_angle(a.angle_left, b.angle_left, s);
  out.angle_right = lerp_angle(a.angle_right, b.angle_right, s);
  out.angle_up = lerp_angle(a.angle_up, b.angle_up, s);
  out.angle_down = lerp_angle(a.angle_down, b.angle_down, s);
  return out;
}

PoseTrace with_same_header(const PoseTrace& trace) {
  PoseTrace out;
  out.has_eye_poses = trace.has_eye_poses;
  out.has_fov = trace.has_fov;
  out.comments = trace.comments;
  out.warnings = trace.warnings;
  return out;
}

}  // namespace

glm::dquat slerp_shortest(const glm::dquat& a, const glm::dquat& b_in, double s) {
  glm::dquat b = b_in;
  if (glm::dot(a, b) < 0.0) b = -b;  // -b is the same rotation, and nearer
  // The angle from |b - a| and |b + a| (unit quaternions) stays accurate for tiny angles, where acos of
  // the dot product loses half its digits.
  const double theta = 2.0 * std::atan2(glm::length(b - a), glm::length(b + a));
  const double sin_theta = std::sin(theta);
  glm::dquat out;
  if (sin_theta < 1e-12) {
    out = a * (1.0 - s) + b * s;  // equal to rounding: the blend is exact and avoids 0/0
  } else {
    out = a * (std::sin((1.0 - s) * theta) / sin_theta) + b * (std::sin(s * theta) / sin_theta);
  }
  return glm::normalize(out);
}

TraceSample PoseTrace::sample(double t) const {
  if (samples.empty()) throw std::logic_error("PoseTrace::sample on an empty trace");
  if (!(t > samples.front().time)) return samples.front();  // also NaN
  if (t >= samples.back().time) return samples.back();
  // First sample strictly later than t; the one before it is at or before t, so dt > 0.
  const auto later = std::upper_bound(samples.begin(), samples.end(), t,
                                      [](double value, const TraceSample& s) { return value < s.time; });
  const TraceSample& a = *(later - 1);
  const TraceSample& b = *later;
  const double s = (t - a.time) / (b.time - a.time);
  TraceSample out;
  out.time = t;
  out.head = interpolate_pose(a.head, b.head, s);
  if (has_eye_poses) {
    for (int i = 0; i < 2; ++i) out.eye[i] = interpolate_pose(a.eye[i], b.eye[i], s);
  }
  if (has_fov) {
    for (int i = 0; i < 2; ++i) out.fov[i] = interpolate_fov(a.fov[i], b.fov[i], s);
  }
  return out;
}

PoseTrace resample_trace(const PoseTrace& trace, double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
    throw std::invalid_argument("resample_trace: the rate must be a positive number of Hz");
  }
  if (trace.empty()) throw std::invalid_argument("resample_trace: empty trace");
  // A small tolerance so that a duration that is an exact multiple of the period keeps its last sample.
  const double intervals = std::floor(trace.duration() * rate_hz + 1e-6);
  if (intervals + 1.0 > kMaxResampledRows) {
    throw std::invalid_argument("resample_trace: " + std::to_string(intervals + 1.0) + " rows is too many");
  }
  const auto count = static_cast<std::size_t>(intervals) + 1;
  PoseTrace out = with_same_header(trace);
  out.samples.reserve(count);
  const double start = trace.start_time();
  for (std::size_t i = 0; i < count; ++i) {
    TraceSample s = trace.sample(start + static_cast<double>(i) / rate_hz);
    s.time = start + static_cast<double>(i) / rate_hz;  // also for the clamped last one
    out.samples.push_back(s);
  }
  return out;
}

PoseTrace truncate_trace(const PoseTrace& trace, double max_seconds) {
  PoseTrace out = with_same_header(trace);
  const double start = trace.start_time();
  for (const TraceSample& s : trace.samples) {
    if (s.time - start > max_seconds) break;
    out.samples.push_back(s);
  }
  return out;
}

}  // namespace dhr
