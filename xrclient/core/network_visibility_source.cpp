#include "core/network_visibility_source.hpp"

#include <utility>

namespace dhr::client {

std::optional<VisibilityFormat> NetworkVisibilitySource::format() const {
  const std::optional<Welcome> w = client_->welcome();
  if (!w) return std::nullopt;
  VisibilityFormat f;
  f.buffer = Extent{w->buffer_width, w->buffer_height};
  // The Welcome's guard band is per side; projection.hpp's GuardBand counts both sides.
  f.guard = GuardBand{2u * w->guard_x, 2u * w->guard_y};
  f.light_count = w->light_count;
  return f;
}

bool NetworkVisibilitySource::take_newest(uint32_t eye, VisibilityFrame& out) {
  EyeVisibility& v = scratch_[eye];
  if (!client_->take_newest(eye == 0 ? Eye::kLeft : Eye::kRight, v)) return false;
  ++taken_;
  out.frame_number = v.frame_number;
  out.view = v.view;
  out.complete = v.complete;
  out.received_ns = v.received_ns;
  // Swap rather than copy: the client recycles `v`'s storage on the next take.
  std::swap(out.buffer, v.buffer);
  if (v.complete) {
    out.row_valid.clear();
  } else {
    std::swap(out.row_valid, v.row_valid);
  }
  return true;
}

VisibilitySourceStats NetworkVisibilitySource::stats() const {
  VisibilitySourceStats s;
  s.frames_received = taken_;
  s.bytes_received = bytes_received_ ? bytes_received_() : 0;
  return s;
}

}  // namespace dhr::client
