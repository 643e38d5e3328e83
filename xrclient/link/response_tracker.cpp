#include "link/response_tracker.hpp"

#include <algorithm>

namespace dhr::client {

ResponseTracker::ResponseTracker(size_t capacity) : ring_(std::max<size_t>(capacity, 1)) {}

void ResponseTracker::on_pose_sent(uint64_t frame, int64_t send_ns) {
  Entry& e = ring_[frame % ring_.size()];
  e = Entry{true, frame, send_ns, {-1, -1}};
}

const ResponseTracker::Entry* ResponseTracker::find(uint64_t frame) const {
  const Entry& e = ring_[frame % ring_.size()];
  return e.used && e.frame == frame ? &e : nullptr;
}

std::optional<int64_t> ResponseTracker::on_eye_complete(uint64_t frame, Eye eye, int64_t usable_ns) {
  const size_t eye_index = static_cast<size_t>(eye);
  if (eye_index > 1 || !find(frame)) return std::nullopt;
  Entry& e = ring_[frame % ring_.size()];
  if (e.complete_ns[eye_index] >= 0) return std::nullopt;  // already counted
  e.complete_ns[eye_index] = usable_ns;
  if (e.complete_ns[0] < 0 || e.complete_ns[1] < 0) return std::nullopt;
  const int64_t response = std::max(e.complete_ns[0], e.complete_ns[1]) - e.send_ns;
  summary_.min_ns = summary_.count ? std::min(summary_.min_ns, response) : response;
  summary_.max_ns = summary_.count ? std::max(summary_.max_ns, response) : response;
  summary_.sum_ns += response;
  summary_.last_ns = response;
  ++summary_.count;
  return response;
}

std::optional<int64_t> ResponseTracker::response_ns(uint64_t frame) const {
  const Entry* e = find(frame);
  if (!e || e->complete_ns[0] < 0 || e->complete_ns[1] < 0) return std::nullopt;
  return std::max(e->complete_ns[0], e->complete_ns[1]) - e->send_ns;
}

std::optional<int64_t> ResponseTracker::pose_sent_ns(uint64_t frame) const {
  const Entry* e = find(frame);
  return e ? std::optional<int64_t>(e->send_ns) : std::nullopt;
}

}  // namespace dhr::client
