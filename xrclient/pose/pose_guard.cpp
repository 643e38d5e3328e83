#include "pose/pose_guard.hpp"

#include <cmath>

#include "log/log.hpp"

namespace dhr::client {

std::optional<std::string> PoseGuard::check(const View& view) {
  return validate_view(view);
}

bool PoseGuard::filter(uint64_t frame, std::array<View, 2>& views) {
  for (uint32_t e = 0; e < 2; ++e) {
    if (auto err = check(views[e])) {
      ++rejected_;
      constexpr uint64_t kLoggedFirst = 5;
      if (rejected_ <= kLoggedFirst || rejected_ % 100 == 0) {
        log::warn("pose: frame %llu, eye %u rejected (%s); reusing the last valid pose (%llu rejected so far)",
                  static_cast<unsigned long long>(frame), e, err->c_str(),
                  static_cast<unsigned long long>(rejected_));
      }
      views = last_valid_;
      return true;
    }
  }
  for (View& v : views) v.pose = normalized(v.pose);
  last_valid_ = views;
  return false;
}

}  // namespace dhr::client
