// --render-path: which passes an eye takes. Vulkan-free, so the shipped defaults (plan/shipped_defaults.hpp),
// dhr-eval and client_bench can name it; the client's setup applies it to render::EyePipelineOptions::forward.
#pragma once
#include <optional>
#include <string_view>

namespace dhr::client {

enum class RenderPath {
  kAuto,      // the forward pass where it applies, except on a discrete GPU (forward_pass_for)
  kForward,   // the forward pass where it applies: one raster pass warps and shades each fragment
  kDeferred,  // always the deferred passes: G-buffer, compute warp, compute shading (each pixel shaded once)
};

// Whether an eye takes the forward pass (where it applies: the paper's warp or edges, the shaded view, at most 8
// lights) on a device. Auto leaves it on discrete GPUs: on the one measured with the shipped warp (an NVIDIA H200,
// 1832x1920 per eye) the deferred passes cost about half of it, because the forward pass also shades the fragments
// a nearer surface later covers (docs/performance.md, "On a GPU": living room 6.63 against 13.66 ms per eye,
// area-lit room 15.31 against 31.19, one run each); on an H100 the paper's warp took 0.70 of its forward time there. A CPU rasterizer (lavapipe) and integrated GPUs, a standalone
// headset's, keep it: on lavapipe the demo ran faster on it (docs/client.md) and client_bench finds the two within
// 6 % at 320x240 (docs/performance.md); no integrated GPU was measured.
inline bool forward_pass_for(RenderPath path, bool discrete_gpu) {
  return path == RenderPath::kForward || (path == RenderPath::kAuto && !discrete_gpu);
}

inline const char* to_string(RenderPath path) {
  switch (path) {
    case RenderPath::kAuto: return "auto";
    case RenderPath::kForward: return "forward";
    case RenderPath::kDeferred: return "deferred";
  }
  return "?";
}

inline std::optional<RenderPath> parse_render_path(std::string_view text) {
  if (text == "auto") return RenderPath::kAuto;
  if (text == "forward") return RenderPath::kForward;
  if (text == "deferred") return RenderPath::kDeferred;
  return std::nullopt;
}

}  // namespace dhr::client
