// Per-frame history of the poses the client rendered, by frame number: the paper's schedule shows frame
// n-p+x with the pose of that frame, and a frame's pose must still be known when its visibility arrives p
// frames later. A fixed ring: frame n lives in slot n % capacity, overwritten capacity frames later.
#pragma once
#include <cstdint>
#include <vector>

#include "math/pose.hpp"

namespace dhr::client {

class ViewHistory {
 public:
  // Throws std::invalid_argument for capacity 0.
  explicit ViewHistory(size_t capacity);

  void record(const FramePose& pose);
  // The pose of `frame` if it is still in the ring (valid until the next record()), else null.
  const FramePose* find(uint64_t frame) const;
  size_t capacity() const { return entries_.size(); }

 private:
  struct Entry {
    bool used = false;
    FramePose pose;
  };
  std::vector<Entry> entries_;
};

}  // namespace dhr::client
