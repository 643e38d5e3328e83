#include "core/view_history.hpp"

#include <stdexcept>

namespace dhr::client {

ViewHistory::ViewHistory(size_t capacity) : entries_(capacity) {
  if (capacity == 0) throw std::invalid_argument("ViewHistory needs capacity >= 1");
}

void ViewHistory::record(uint64_t frame, int64_t display_time_ns, const std::array<View, 2>& views) {
  Entry& e = entries_[frame % entries_.size()];
  e.used = true;
  e.frame = frame;
  e.display_time_ns = display_time_ns;
  e.views = views;
}

const ViewHistory::Entry* ViewHistory::entry(uint64_t frame) const {
  const Entry& e = entries_[frame % entries_.size()];
  return e.used && e.frame == frame ? &e : nullptr;
}

std::optional<std::array<View, 2>> ViewHistory::find(uint64_t frame) const {
  const Entry* e = entry(frame);
  if (e == nullptr) return std::nullopt;
  return e->views;
}

std::optional<int64_t> ViewHistory::display_time(uint64_t frame) const {
  const Entry* e = entry(frame);
  if (e == nullptr) return std::nullopt;
  return e->display_time_ns;
}

}  // namespace dhr::client
