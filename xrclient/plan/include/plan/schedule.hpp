// Which frame's pose an eye shows, given the newest visibility it has (DESIGN.md, terms):
//   p = n - m (the visibility is of frame m), x = min(x_max, p).
//   kPaper:  show frame n - p + x (= m + x) with that frame's pose and G-buffer, warping the buffer x frames.
//   kNewest: always show frame n (the newest pose), warping the buffer over all p frames.
//   kStale:  show frame n and use the buffer as if it had been traced for frame n's view: no warp at all
//            (the reference that shows what warping buys).
// Without visibility every schedule shows frame n.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace dhr::client {

enum class Schedule { kNewest, kPaper, kStale };

const char* schedule_name(Schedule schedule);  // "newest" | "paper" | "stale"
std::optional<Schedule> parse_schedule(const std::string& text);

struct ScheduleDecision {
  uint64_t display_frame = 0;  // whose pose (and G-buffer) is shown
  uint64_t age = 0;            // p: frames between the visibility and frame n (0 without visibility)
  uint64_t predicted = 0;      // x: frames the warp spans, display_frame - visibility frame (0 for kStale)
};

// visibility_frame: the frame the newest visibility was traced for (a value above n counts as n).
ScheduleDecision decide_schedule(Schedule schedule, uint64_t x_max, uint64_t frame,
                                 std::optional<uint64_t> visibility_frame);

}  // namespace dhr::client
