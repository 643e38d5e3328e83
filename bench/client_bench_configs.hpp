// client_bench's configurations and how they are measured (client_bench.cpp, client_bench_many.cpp).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dhr::vk {
class Context;
}

namespace dhr::bench {

// One configuration: renders frame i (submitted and waited for) and gives its GPU ms per eye (none without
// timestamps).
struct Config {
  std::string name;
  std::function<std::vector<double>(uint32_t)> run;
  std::vector<double> samples;
};

// A configuration of one eye pipeline pass sequence: records a frame into a command buffer and, after the
// submission completed, gives its GPU ms.
Config single_eye_config(const vk::Context& context, std::string name,
                         std::function<void(VkCommandBuffer, uint32_t)> record,
                         std::function<std::optional<double>()> time_ms);

// Frame by frame, every configuration in turn, so that drifts of a shared machine touch them alike; the first
// `warmup` frames are not kept.
void measure(uint32_t warmup, uint32_t frames, std::vector<Config>& configs);

}  // namespace dhr::bench
