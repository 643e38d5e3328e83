// One received visibility frame of one eye, as the client holds it from reassembly to the renderer: the
// buffer, the view and scene time it was traced for, and which rows arrived. The network client publishes
// it, the frame planner keeps the newest per eye, and the warp pass reads it; it is moved (or swapped) on the
// way, never copied, except once out of the reassembler, which keeps receiving into its own storage.
#pragma once
#include "math/pose.hpp"
#include "protocol/protocol.hpp"
#include "visibility/visibility.hpp"

#include <cstdint>
#include <vector>

namespace dhr {

struct VisibilityFrame {
  uint64_t frame_number = 0;       // the client frame whose pose was traced
  Eye eye = Eye::kLeft;
  View view;                       // the view the server traced (display FOV; the guard band widens it)
  int64_t scene_time_ns = 0;       // the scene time it was traced for (ns since the session's start; DESIGN 5b)
  VisibilityBuffer buffer;         // the traced (guard-banded) size; rows that did not arrive are zero
  std::vector<uint8_t> row_valid;  // per row: 1 when the whole row arrived (read only when !complete)
  uint32_t rows_valid = 0;
  bool complete = false;
  int64_t received_ns = 0;         // client clock, when it was published (became usable)
};

}  // namespace dhr
