#include "eval_trace_gen.hpp"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <numbers>

namespace dhr::eval {

PoseTrace synthetic_head_trace(double seconds, double rate_hz) {
  PoseTrace trace;
  trace.comments.push_back("dhr-eval make-trace: synthetic 6-DoF head motion (sums of sines), " +
                           std::to_string(rate_hz) + " Hz");
  const double two_pi = 2.0 * std::numbers::pi;
  const auto count = static_cast<long>(std::floor(seconds * rate_hz + 1e-9)) + 1;
  for (long i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / rate_hz;
    TraceSample s;
    s.time = t;
    // A slow step sideways and forward with a little bob, as when leaning and walking in place.
    s.head.position = glm::dvec3(0.25 * std::sin(two_pi * 0.15 * t), 0.02 * std::sin(two_pi * 1.8 * t),
                                 -0.15 * std::sin(two_pi * 0.1 * t));
    // Looking around: yaw up to ~40 degrees (peak ~90 deg/s), pitch ~12, a little roll.
    const double yaw = 0.7 * std::sin(two_pi * 0.3 * t) + 0.1 * std::sin(two_pi * 1.1 * t);
    const double pitch = 0.2 * std::sin(two_pi * 0.45 * t + 1.0);
    const double roll = 0.05 * std::sin(two_pi * 0.2 * t);
    s.head.orientation = glm::normalize(glm::angleAxis(yaw, glm::dvec3(0, 1, 0)) *
                                        glm::angleAxis(pitch, glm::dvec3(1, 0, 0)) *
                                        glm::angleAxis(roll, glm::dvec3(0, 0, 1)));
    trace.samples.push_back(s);
  }
  return trace;
}

}  // namespace dhr::eval
