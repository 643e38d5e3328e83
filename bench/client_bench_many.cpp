#include "client_bench_many.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "bench_timing.hpp"
#include "client_bench_configs.hpp"
#include "plan/shipped_defaults.hpp"
#include "render/client_scene.hpp"
#include "render/eye_pipeline.hpp"
#include "render/forward_pass.hpp"
#include "render/render_camera.hpp"
#include "vk/context.hpp"
#include "vk/timestamps.hpp"

namespace dhr::bench {

int run_many_lights(const std::string& scene_path, const Scene& scene, Extent size, const View& view,
                    const VisibilityInput& input, uint32_t warmup, uint32_t frames) {
  vk::ContextOptions vk_options;
  vk_options.app_name = "client_bench";
  const std::unique_ptr<vk::Context> context = vk::Context::create(vk_options);
  const render::ClientScene gpu_scene(*context, scene);
  const LightSlots& slots = gpu_scene.light_slots();

  nlohmann::ordered_json out;
  out["bench"] = "client_bench";
  out["scene"] = std::filesystem::path(scene_path).filename().string();
  out["size"] = std::to_string(size.width) + "x" + std::to_string(size.height);
  out["lights"] = scene.lights.size();
  out["light_slots"] = slots.slot_count();
  out["lights_per_cell_max"] = slots.max_lights_per_cell();
  out["lights_without_slot"] = slots.dropped().size();
  out["device"] = context->info().name;
  out["frames"] = frames;
  out["local"] = "none: the client's shadow maps hold at most 32 lights";
  std::fprintf(stderr, "client_bench: %s\n", slots.describe().c_str());

  std::vector<Config> configs;
  // DHR: the eye pipeline (deferred with light slots) with the warp dhr-xrclient ships for such a scene: the shipped
  // warp without the shadow maps it cannot have (StereoPipeline does the same).
  render::EyePipelineOptions deferred;
  deferred.frames_in_flight = 1;
  deferred.forward = false;
  deferred.warp = render::warp_settings_for(client::resolve_warp(client::shipped::kWarp, scene.has_soft_lights()),
                                            client::shipped::kDepthScale)
                      .without_shadow_maps();
  render::EyePipeline eye(*context, gpu_scene, size, deferred);
  render::EyeStats eye_stats;
  configs.push_back(single_eye_config(
      *context, "dhr_deferred_ms",
      [&](VkCommandBuffer cmd, uint32_t) {
        eye.prepare(cmd, 0, input);
        eye.record(cmd, 0, view, input);
      },
      [&]() -> std::optional<double> {
        eye_stats = eye.read_stats(0);
        if (!eye_stats.gpu.valid) return std::nullopt;
        return eye_stats.gpu.total_ms;
      }));
  // Forward without shadows, every light by the slots' grid.
  render::ForwardOptions fo;
  fo.mode = render::ForwardMode::kLambert;
  render::ForwardPass lambert(*context, gpu_scene, fo);
  render::ForwardTargets targets = render::ForwardTargets::create(*context, size, fo);
  vk::TimestampQueries stamps(*context, 2);
  render::ForwardFrame frame;
  frame.display = render::display_camera(view, size);
  frame.lights = scene.lights;
  configs.push_back(single_eye_config(
      *context, "forward_ms",
      [&](VkCommandBuffer cmd, uint32_t) {
        stamps.reset(cmd);
        stamps.write(cmd, 0);
        lambert.record(cmd, 0, frame, targets);
        stamps.write(cmd, 1);
      },
      [&]() -> std::optional<double> {
        const std::vector<double> ns = stamps.read_ns();
        if (ns.size() != 2) return std::nullopt;
        return (ns[1] - ns[0]) * 1e-6;
      }));
  std::fprintf(stderr, "client_bench: %zu configurations, %u + %u frames each\n", configs.size(), warmup, frames);
  measure(warmup, frames, configs);
  for (const Config& c : configs) {
    if (c.samples.empty()) throw std::runtime_error("no GPU timestamps on " + context->info().name + ": nothing to measure");
    out[c.name] = median(c.samples, std::nan(""));
  }
  out["dhr_path"] = eye_stats.forward ? "forward" : "deferred";
  out["dhr_deferred_vs_forward"] = out["dhr_deferred_ms"].get<double>() / out["forward_ms"].get<double>();
  out["dhr_known_frac"] = eye_stats.warp.surface() == 0
                              ? 0.0
                              : static_cast<double>(eye_stats.warp[render::WarpStatus::kKnown]) /
                                    static_cast<double>(eye_stats.warp.surface());
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace dhr::bench
