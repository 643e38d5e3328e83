// client_bench's configurations and how they are measured (client_bench.cpp, client_bench_many.cpp), and its
// scene and size arguments.
#pragma once
#include <vulkan/vulkan.h>

#include "math/projection.hpp"
#include "scene/scene.hpp"

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

// --size WxH: 1..8192 per axis, or nullopt.
std::optional<Extent> parse_size(const std::string& text);

// Point lights beyond the scene's, up to `count` (at most kMaxLights): copies of its point (or spot, rect, disk)
// lights in turn, each moved by a fixed pattern of up to 0.6 m and dimmed by the number of copies. Throws
// cli::InputError when the scene has no such light to copy.
void add_lights(Scene& scene, uint32_t count);

}  // namespace dhr::bench
