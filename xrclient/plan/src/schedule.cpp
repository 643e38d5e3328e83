#include "plan/schedule.hpp"

#include <algorithm>

namespace dhr::client {

const char* schedule_name(Schedule schedule) {
  switch (schedule) {
    case Schedule::kPaper: return "paper";
    case Schedule::kStale: return "stale";
    case Schedule::kNewest: break;
  }
  return "newest";
}

std::optional<Schedule> parse_schedule(const std::string& text) {
  if (text == "paper") return Schedule::kPaper;
  if (text == "newest") return Schedule::kNewest;
  if (text == "stale") return Schedule::kStale;
  return std::nullopt;
}

ScheduleDecision decide_schedule(Schedule schedule, uint64_t x_max, uint64_t frame,
                                 std::optional<uint64_t> visibility_frame) {
  ScheduleDecision d;
  d.display_frame = frame;
  if (!visibility_frame) return d;
  const uint64_t m = std::min(*visibility_frame, frame);
  d.age = frame - m;
  if (schedule == Schedule::kStale) return d;
  if (schedule == Schedule::kPaper) d.display_frame = m + std::min(x_max, d.age);
  d.predicted = d.display_frame - m;
  return d;
}

}  // namespace dhr::client
