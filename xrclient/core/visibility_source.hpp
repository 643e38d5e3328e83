// Where the frame loop gets its visibility: the network client (VisibilityClient, xrclient/net) in the
// executable, an in-process tracer in tests. The frame coordinator only talks to this interface, so the same
// loop runs in every mode (DESIGN.md, data flow). Every call is non-blocking: the loop never waits for it.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.hpp"
#include "core/projection.hpp"
#include "core/visibility.hpp"

namespace dhr::client {

// The newest visibility of one eye, with the view it was traced for.
struct VisibilityFrame {
  uint64_t frame_number = 0;       // the client frame whose pose was traced
  View view;                       // the view the server traced (display FOV; the guard band is added on top)
  VisibilityBuffer buffer;         // guard-banded size (Welcome's buffer size)
  std::vector<uint8_t> row_valid;  // empty when complete, else one entry per row (0 = missing)
  bool complete = true;
  int64_t received_ns = 0;         // when it became available (source clock)
};

// What the session agreed on (the Welcome): traced buffer size and guard band per side.
struct VisibilityFormat {
  Extent buffer;        // traced size per eye, guard band included
  GuardBand guard;      // total extra pixels per axis (both sides together), as projection.hpp's GuardBand
  uint32_t light_count = 0;
};

struct VisibilitySourceStats {
  uint64_t frames_received = 0;   // eye buffers handed out by take_newest
  uint64_t bytes_received = 0;    // visibility payload bytes (compressed) received so far
};

class VisibilitySource {
 public:
  virtual ~VisibilitySource() = default;
  // Housekeeping once per frame (resend Hello, heartbeats, timeouts). Never blocks.
  virtual void tick() = 0;
  // The session format once agreed; std::nullopt before that.
  virtual std::optional<VisibilityFormat> format() const = 0;
  // The session cannot continue (no server answered, server said Bye); failure() says why in one line.
  virtual bool failed() const = 0;
  virtual std::string failure() const = 0;
  // Fire and forget.
  virtual void send_pose(uint64_t frame, int64_t display_time_ns, const std::array<View, 2>& views) = 0;
  // The newest visibility of `eye` when it is newer than what was taken last time; false otherwise.
  virtual bool take_newest(uint32_t eye, VisibilityFrame& out) = 0;
  // Pose sent -> visibility of that frame complete (both eyes), nanoseconds; std::nullopt when unknown.
  virtual std::optional<int64_t> response_ns(uint64_t frame) const = 0;
  virtual VisibilitySourceStats stats() const = 0;
};

}  // namespace dhr::client
