// The newest visibility of one eye as the warp pass consumes it (the frame planner fills it in).
#pragma once
#include <cstdint>
#include <span>

#include "math/projection.hpp"
#include "visibility/visibility.hpp"

namespace dhr {

struct VisibilityInput {
  const VisibilityBuffer* buffer = nullptr;  // null: nothing received yet (every surface pixel unknown)
  Camera traced;                             // the guard-banded camera it was traced for (extent = buffer size)
  std::span<const uint8_t> row_valid;        // empty: every row arrived; else one entry per row, 0 = missing
  uint64_t key = 0;  // non-zero: identifies the contents; a slot already holding this key skips the upload
  int64_t scene_time_ns = 0;  // the scene time it was traced for (the warp's motion rule compares it to the display's)
};

}  // namespace dhr
