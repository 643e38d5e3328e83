// A small synthetic 6-DoF head trace (sums of sines: walking sway, looking around, nodding), written in the
// canonical CSV format, for scenes and machines without the recorded traces of ../shared/data.
#pragma once
#include "traces/pose_trace.hpp"

namespace dhr::eval {

// Deterministic: the same seconds and rate give the same trace. Head at the origin, facing -Z.
PoseTrace synthetic_head_trace(double seconds, double rate_hz);

}  // namespace dhr::eval
