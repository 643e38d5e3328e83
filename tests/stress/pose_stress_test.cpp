// Pose streams: a million composed small rotations stay unit and on the analytic rotation (renormalized
// after every composition); NaN / Inf / zero quaternions and huge translations in pose input, in trace
// files and in PoseUpdate datagrams are rejected with a clear message, counted, and never reach a
// decoded message or a trace.
#include "math/pose.hpp"
#include "traces/pose_trace.hpp"
#include "protocol/protocol.hpp"
#include "protocol/protocol_error.hpp"
#include "stress_support.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace dhr::stress {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Rotation angle of a^-1 b, from its vector part (acos near 1 would lose half the digits).
double angle_between(const glm::dquat& a, const glm::dquat& b) {
  const glm::dquat r = glm::conjugate(glm::normalize(a)) * glm::normalize(b);
  return 2.0 * std::atan2(glm::length(glm::dvec3(r.x, r.y, r.z)), std::fabs(r.w));
}

TEST(StressPoses, MillionComposedSmallRotationsStayOnTheAnalyticRotation) {
  const size_t frames = pick<size_t>(1'000'000, 20'000'000);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, 1.0, -0.2));
  const double step = 1e-4;  // rad per frame (0.5 degrees per second at 90 Hz)
  Pose delta;
  delta.orientation = glm::angleAxis(step, axis);
  delta.position = glm::dvec3(0.0, 0.0, -1e-3);  // 1 mm forward per frame, in the head's own frame
  Pose renormalized, raw;
  double worst_norm_renormalized = 0.0, worst_norm_raw = 0.0;
  for (size_t i = 0; i < frames; ++i) {
    renormalized = normalized(renormalized * delta);
    raw = raw * delta;  // what happens without renormalization (reported, not bounded)
    if (i % 1024 == 0 || i + 1 == frames) {
      worst_norm_renormalized = std::max(worst_norm_renormalized, std::fabs(glm::length(renormalized.orientation) - 1.0));
      worst_norm_raw = std::max(worst_norm_raw, std::fabs(glm::length(raw.orientation) - 1.0));
      ASSERT_FALSE(validate_pose(renormalized).has_value()) << "frame " << i;
    }
  }
  // The analytic result: one rotation by frames * step about the axis; the path is a circle (every step
  // turns the 1 mm move by the same angle), whose chord is 2 r sin(total / 2) with r = 1 mm / (2 sin(step/2)).
  const double total = double(frames) * step;
  const double angle_error = angle_between(renormalized.orientation, glm::angleAxis(std::fmod(total, 4.0 * glm::pi<double>()), axis));
  const glm::dvec3 forward_perp = glm::dvec3(0.0, 0.0, -1.0) - axis * glm::dot(glm::dvec3(0.0, 0.0, -1.0), axis);
  const double radius = 1e-3 * glm::length(forward_perp) / (2.0 * std::sin(step / 2.0));
  const double along_axis = double(frames) * 1e-3 * glm::dot(glm::dvec3(0.0, 0.0, -1.0), axis);
  const double chord = 2.0 * radius * std::fabs(std::sin(total / 2.0));
  const double expected_distance = std::sqrt(chord * chord + along_axis * along_axis);
  const double position_error = std::fabs(glm::length(renormalized.position) - expected_distance);

  report("pose_stream_1e6_rotations", "unit_norm_drift_renormalized", worst_norm_renormalized, 1e-14);
  report("pose_stream_1e6_rotations", "unit_norm_drift_without_renormalization", worst_norm_raw, 1.0);
  report("pose_stream_1e6_rotations", "angle_error_rad", angle_error, 1e-9);
  report("pose_stream_1e6_rotations", "position_error_m", position_error, 1e-6);
  EXPECT_LE(worst_norm_renormalized, 1e-14);
  EXPECT_LE(angle_error, 1e-9);
  EXPECT_LE(position_error, 1e-6);
}

struct BadPose {
  const char* what;
  Pose pose;
};

std::vector<BadPose> bad_poses() {
  std::vector<BadPose> out;
  auto add = [&](const char* what, glm::dvec3 p, glm::dquat q) {
    Pose pose;
    pose.position = p;
    pose.orientation = q;
    out.push_back({what, pose});
  };
  const glm::dquat unit(1.0, 0.0, 0.0, 0.0);
  add("NaN position", {kNaN, 0, 0}, unit);
  add("Inf position", {0, -kInf, 0}, unit);
  add("NaN quaternion", {0, 1.6, 0}, glm::dquat(kNaN, 0, 0, 0));
  add("Inf quaternion", {0, 1.6, 0}, glm::dquat(1, kInf, 0, 0));
  add("zero quaternion", {0, 1.6, 0}, glm::dquat(0, 0, 0, 0));
  add("denormal quaternion", {0, 1.6, 0}, glm::dquat(1e-310, 0, 0, 0));
  add("huge translation", {2e6, 0, 0}, unit);
  add("absurd translation", {0, 1e300, 0}, unit);
  return out;
}

TEST(StressPoses, BadPoseInputIsRejectedWithAMessage) {
  size_t rejected = 0;
  for (const BadPose& b : bad_poses()) {
    const auto error = validate_pose(b.pose);
    ASSERT_TRUE(error.has_value()) << b.what;
    EXPECT_FALSE(error->empty());
    EXPECT_EQ(error->find('\n'), std::string::npos) << "one line";
    std::printf("[stress] pose input %-20s -> %s\n", b.what, error->c_str());
    ++rejected;
  }
  EXPECT_EQ(rejected, bad_poses().size());
  report("bad_pose_input", "accepted_bad_poses", double(bad_poses().size() - rejected), 0.0);
}

TEST(StressPoses, BadTraceRowsAreRejectedWithTheirLine) {
  const std::string header = "# dhr-trace v1\nt,x,y,z,qx,qy,qz,qw\n";
  const std::string good = "0,0,1.6,0,0,0,0,1\n";
  const std::vector<std::pair<const char*, std::string>> rows = {
      {"NaN position", "0.1,nan,1.6,0,0,0,0,1\n"},      {"Inf position", "0.1,0,inf,0,0,0,0,1\n"},
      {"NaN quaternion", "0.1,0,1.6,0,nan,0,0,1\n"},    {"zero quaternion", "0.1,0,1.6,0,0,0,0,0\n"},
      {"huge translation", "0.1,5e6,1.6,0,0,0,0,1\n"},  {"absurd translation", "0.1,0,1e300,0,0,0,0,1\n"},
      {"Inf time", "inf,0,1.6,0,0,0,0,1\n"}};
  size_t rejected = 0;
  for (const auto& [what, row] : rows) {
    // The bad row in the middle (a bad final line may be dropped as an interrupted recording).
    const TraceReadResult r = parse_pose_trace(header + good + row + "0.2,0,1.6,0,0,0,0,1\n", "stress.csv");
    EXPECT_FALSE(r.ok()) << what;
    if (r.ok()) continue;
    EXPECT_NE(r.error.find("stress.csv:4"), std::string::npos) << what << ": " << r.error;
    EXPECT_EQ(r.error.find('\n'), std::string::npos);
    std::printf("[stress] trace row %-20s -> %s\n", what, r.error.c_str());
    ++rejected;
  }
  report("bad_trace_rows", "accepted_bad_rows", double(rows.size() - rejected), 0.0);
  EXPECT_EQ(rejected, rows.size());
}

TEST(StressPoses, BadPosesInDatagramsAreRejectedAndCounted) {
  std::vector<std::pair<std::string, PoseUpdate>> updates;
  for (const BadPose& b : bad_poses()) {
    for (const int eye : {0, 1}) {
      PoseUpdate u;
      u.frame = 7;
      u.display_time_ns = 1'000'000;
      u.views[0].pose.position = {0.0, 1.6, 0.0};
      u.views[1].pose.position = {0.06, 1.6, 0.0};
      u.views[eye].pose = b.pose;
      updates.push_back({std::string(b.what) + (eye ? " (right)" : " (left)"), u});
    }
  }
  for (const float bad_angle : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 1.6f}) {
    PoseUpdate u;
    u.views[1].fov.angle_right = bad_angle;
    updates.push_back({"bad FOV angle", u});
  }
  // Control: the same datagram with good poses decodes (so the rejections are about the poses).
  {
    Datagram good;
    good.session_token = 42;
    good.message = PoseUpdate{};
    Datagram out;
    ASSERT_EQ(decode_datagram(encode_datagram(good), out), DecodeError::kNone);
  }
  size_t rejected = 0;
  for (const auto& [what, update] : updates) {
    Datagram d;
    d.session_token = 42;
    d.sequence = 1;
    d.message = update;
    const std::vector<uint8_t> bytes = encode_datagram(d);
    ASSERT_FALSE(bytes.empty()) << what;
    Datagram out;
    const DecodeError e = decode_datagram(bytes, out);
    EXPECT_NE(e, DecodeError::kNone) << what;
    if (e != DecodeError::kNone) {
      ++rejected;
      std::printf("[stress] datagram %-28s -> %s\n", what.c_str(), to_string(e));
    }
  }
  report("bad_pose_datagrams", "accepted_bad_datagrams", double(updates.size() - rejected), 0.0);
  EXPECT_EQ(rejected, updates.size());
}

}  // namespace
}  // namespace dhr::stress
