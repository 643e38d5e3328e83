// Where the frame loop gets its visibility: the network client (VisibilityClient, xrclient/link) in the
// executable, an in-process tracer in tests. The frame coordinator only talks to this interface, so the same
// loop runs in every mode (DESIGN.md, data flow). Every call is non-blocking: the loop never waits for it.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "math/pose.hpp"
#include "math/projection.hpp"
#include "codec/visibility_frame.hpp"
#include "visibility/visibility.hpp"

namespace dhr::client {

// What the session agreed on (the Welcome): the traced format (display size and guard band per side), the
// lights in every mask, and the hash of the scene content the server traces (0: not known).
struct VisibilityFormat {
  TracedFormat traced;
  uint32_t light_count = 0;
  uint64_t scene_hash = 0;
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
  virtual void send_pose(const FramePose& pose) = 0;
  // The newest visibility of `eye` when it is newer than what was taken last time; false otherwise.
  virtual bool take_newest(uint32_t eye, VisibilityFrame& out) = 0;
  // Pose sent -> visibility of that frame complete (both eyes), nanoseconds; std::nullopt when unknown.
  virtual std::optional<int64_t> response_ns(uint64_t frame) const = 0;
  virtual VisibilitySourceStats stats() const = 0;
};

}  // namespace dhr::client
