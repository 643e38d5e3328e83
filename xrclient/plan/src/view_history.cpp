#include "plan/view_history.hpp"

#include <stdexcept>

namespace dhr::client {

ViewHistory::ViewHistory(size_t capacity) : entries_(capacity) {
  if (capacity == 0) throw std::invalid_argument("ViewHistory needs capacity >= 1");
}

void ViewHistory::record(const FramePose& pose) {
  Entry& e = entries_[pose.frame % entries_.size()];
  e.used = true;
  e.pose = pose;
}

const FramePose* ViewHistory::find(uint64_t frame) const {
  const Entry& e = entries_[frame % entries_.size()];
  return e.used && e.pose.frame == frame ? &e.pose : nullptr;
}

}  // namespace dhr::client
