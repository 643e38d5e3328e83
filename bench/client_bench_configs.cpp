#include "client_bench_configs.hpp"

#include <cstdio>

#include "vk/context.hpp"

namespace dhr::bench {

Config single_eye_config(const vk::Context& context, std::string name,
                         std::function<void(VkCommandBuffer, uint32_t)> record,
                         std::function<std::optional<double>()> time_ms) {
  return Config{std::move(name),
                [&context, record = std::move(record), time_ms = std::move(time_ms)](uint32_t i) {
                  context.submit_and_wait([&](VkCommandBuffer cmd) { record(cmd, i); });
                  const std::optional<double> ms = time_ms();
                  return ms ? std::vector<double>{*ms} : std::vector<double>{};
                },
                {}};
}

void measure(uint32_t warmup, uint32_t frames, std::vector<Config>& configs) {
  for (uint32_t i = 0; i < warmup + frames; ++i) {
    for (Config& c : configs) {
      const std::vector<double> ms = c.run(i);
      if (i >= warmup) c.samples.insert(c.samples.end(), ms.begin(), ms.end());
    }
    if ((i + 1) % 10 == 0) std::fprintf(stderr, "client_bench: frame %u of %u\n", i + 1, warmup + frames);
  }
}

}  // namespace dhr::bench
