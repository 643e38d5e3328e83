#include "vk/timestamps.hpp"

#include <stdexcept>

#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::vk {

TimestampQueries::TimestampQueries(const Context& context, uint32_t count) : count_(count) {
  if (count == 0) throw std::invalid_argument("TimestampQueries needs at least one query");
  const DeviceInfo& info = context.info();
  if (!info.timestamps_supported) {
    unsupported_reason_ = "device '" + info.name + "' has no timestamp support on its graphics+compute queue";
    return;
  }
  valid_bits_ = info.timestamp_valid_bits;
  period_ns_ = static_cast<double>(info.timestamp_period_ns);
  VkQueryPoolCreateInfo create{};
  create.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
  create.queryType = VK_QUERY_TYPE_TIMESTAMP;
  create.queryCount = count;
  VkQueryPool pool = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateQueryPool(context.device(), &create, nullptr, &pool));
  pool_ = QueryPool(context.device(), pool);
}

void TimestampQueries::reset(VkCommandBuffer cmd) const {
  if (pool_) vkCmdResetQueryPool(cmd, pool_.get(), 0, count_);
}

void TimestampQueries::write(VkCommandBuffer cmd, uint32_t index, VkPipelineStageFlags2 stage) const {
  if (index >= count_) {
    throw std::out_of_range("timestamp index " + std::to_string(index) + " >= count " + std::to_string(count_));
  }
  if (pool_) vkCmdWriteTimestamp2(cmd, stage, pool_.get(), index);
}

std::vector<uint64_t> TimestampQueries::read_ticks() const {
  if (!pool_) return {};
  std::vector<uint64_t> ticks(count_);
  DHR_VK_CHECK(vkGetQueryPoolResults(pool_.device(), pool_.get(), 0, count_, ticks.size() * sizeof(uint64_t),
                                     ticks.data(), sizeof(uint64_t),
                                     VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  if (valid_bits_ < 64) {
    const uint64_t mask = (uint64_t{1} << valid_bits_) - 1;
    for (uint64_t& t : ticks) t &= mask;
  }
  return ticks;
}

std::vector<double> TimestampQueries::read_ns() const {
  const std::vector<uint64_t> ticks = read_ticks();
  std::vector<double> ns(ticks.size());
  const uint64_t mask = valid_bits_ < 64 ? (uint64_t{1} << valid_bits_) - 1 : ~uint64_t{0};
  for (size_t i = 0; i < ticks.size(); ++i) {
    // Unsigned difference modulo the counter width: correct across one wrap-around.
    const uint64_t delta = (ticks[i] - ticks[0]) & mask;
    ns[i] = static_cast<double>(delta) * period_ns_;
  }
  return ns;
}

}  // namespace dhr::vk
