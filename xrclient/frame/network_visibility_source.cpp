#include "frame/network_visibility_source.hpp"

#include <utility>

namespace dhr::client {

std::optional<VisibilityFormat> NetworkVisibilitySource::format() const {
  const std::optional<Welcome> w = client_->welcome();
  if (!w) return std::nullopt;
  return VisibilityFormat{w->format(), w->light_count, w->scene_hash};
}

bool NetworkVisibilitySource::take_newest(uint32_t eye, VisibilityFrame& out) {
  // Swapped, not copied: the client recycles out's old storage on its next publication.
  if (!client_->take_newest(eye == 0 ? Eye::kLeft : Eye::kRight, out)) return false;
  ++taken_;
  return true;
}

VisibilitySourceStats NetworkVisibilitySource::stats() const {
  VisibilitySourceStats s;
  s.frames_received = taken_;
  s.bytes_received = bytes_received_ ? bytes_received_() : 0;
  return s;
}

}  // namespace dhr::client
