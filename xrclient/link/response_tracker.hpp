// ResponseTracker: per frame, when its pose was sent and when each eye's visibility became usable in
// full (client clock), in a fixed ring of the newest frames. Response time = pose sent -> both eyes'
// buffers complete on the client: the whole loop (uplink, server wait and trace, downlink, reassembly),
// measured on one clock, so it needs no clock synchronization. Not thread-safe (the owner's lock).
#pragma once
#include "protocol/protocol.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace dhr::client {

struct ResponseSummary {
  uint64_t count = 0;  // frames with both eyes complete
  int64_t last_ns = 0;
  int64_t min_ns = 0;
  int64_t max_ns = 0;
  int64_t sum_ns = 0;
  int64_t mean_ns() const { return count ? sum_ns / static_cast<int64_t>(count) : 0; }
};

class ResponseTracker {
 public:
  static constexpr size_t kDefaultCapacity = 1024;  // frames remembered (~11 s at 90 Hz)

  explicit ResponseTracker(size_t capacity = kDefaultCapacity);  // capacity >= 1

  void on_pose_sent(uint64_t frame, int64_t send_ns);
  // The eye's buffer of `frame` became complete at `usable_ns`. Returns the frame's response time when
  // this completed both eyes (once per frame); nullopt otherwise or when the frame is not remembered.
  std::optional<int64_t> on_eye_complete(uint64_t frame, Eye eye, int64_t usable_ns);

  std::optional<int64_t> response_ns(uint64_t frame) const;   // both eyes complete
  std::optional<int64_t> pose_sent_ns(uint64_t frame) const;
  const ResponseSummary& summary() const { return summary_; }

 private:
  struct Entry {
    bool used = false;
    uint64_t frame = 0;
    int64_t send_ns = 0;
    std::array<int64_t, 2> complete_ns{-1, -1};
  };
  const Entry* find(uint64_t frame) const;

  std::vector<Entry> ring_;
  ResponseSummary summary_;
};

}  // namespace dhr::client
