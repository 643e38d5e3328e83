// Per-frame history of the views the client rendered with, by frame number: the paper's schedule shows
// frame n-p+x with the pose of that frame, and a frame's pose must still be known when its visibility
// arrives p frames later. A fixed ring: frame n lives in slot n % capacity, overwritten capacity frames later.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/pose.hpp"

namespace dhr::client {

class ViewHistory {
 public:
  // Throws std::invalid_argument for capacity 0.
  explicit ViewHistory(size_t capacity);

  void record(uint64_t frame, int64_t display_time_ns, const std::array<View, 2>& views);
  // The views of `frame` if it is still in the ring.
  std::optional<std::array<View, 2>> find(uint64_t frame) const;
  std::optional<int64_t> display_time(uint64_t frame) const;
  size_t capacity() const { return entries_.size(); }

 private:
  struct Entry {
    bool used = false;
    uint64_t frame = 0;
    int64_t display_time_ns = 0;
    std::array<View, 2> views{};
  };
  const Entry* entry(uint64_t frame) const;
  std::vector<Entry> entries_;
};

}  // namespace dhr::client
