// GPU timestamp queries: a pool of N timestamps written from command buffers, read back in ns.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

#include "vk/handle.hpp"

namespace dhr::vk {

class Context;

class TimestampQueries {
 public:
  TimestampQueries() = default;
  // count >= 1. Without timestamp support no pool is created: supported() is false, reset/write
  // record nothing and the reads return empty vectors.
  TimestampQueries(const Context& context, uint32_t count);

  bool supported() const { return static_cast<bool>(pool_); }
  const std::string& unsupported_reason() const { return unsupported_reason_; }
  uint32_t count() const { return count_; }
  VkQueryPool pool() const { return pool_.get(); }

  // Resets all queries; record before the first write of each use.
  void reset(VkCommandBuffer cmd) const;
  // Writes timestamp `index` once all earlier commands have reached `stage`.
  void write(VkCommandBuffer cmd, uint32_t index,
             VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT) const;

  // Waits until all `count` timestamps are written (each must be written since the last reset).
  // Raw ticks, masked to the queue's valid bits.
  std::vector<uint64_t> read_ticks() const;
  // Nanoseconds relative to timestamp 0 (so values stay exact in a double), using the device's
  // timestamp period; wrap-around of narrow counters is handled.
  std::vector<double> read_ns() const;

 private:
  QueryPool pool_;
  uint32_t count_ = 0;
  uint32_t valid_bits_ = 0;
  double period_ns_ = 0.0;
  std::string unsupported_reason_;
};

}  // namespace dhr::vk
