// --warp: which warp rule the eyes use (render::WarpSettings is made from it in the client's setup). Vulkan-free,
// so the shipped defaults (plan/shipped_defaults.hpp), dhr-eval and client_bench can name it.
#pragma once

namespace dhr::client {

enum class WarpChoice {
  kPaper,  // the paper's warp (unknown pixels lit)
  kFull,   // render::WarpSettings::full() (deferred, with shadow maps)
  kEdges,       // render::WarpSettings::server_edges() (forward, shadow maps where the samples disagree)
  kEdgesDepth,  // render::WarpSettings::server_edges_depth(--depth-scale) (the same plus the depth test)
};

inline const char* to_string(WarpChoice choice) {
  switch (choice) {
    case WarpChoice::kPaper: return "paper";
    case WarpChoice::kFull: return "full";
    case WarpChoice::kEdges: return "edges";
    case WarpChoice::kEdgesDepth: return "edges-depth";
  }
  return "?";
}

// --traced-depth (edges-depth, full): where the depth test's traced depth comes from
// (render::WarpSettings::depth_splat).
enum class TracedDepth {
  kRaster,  // the traced camera rendered: a second raster pass per traced camera
  kSplat,   // the eye's previous display frame's depth moved into the traced camera (one compute pass)
};

inline const char* to_string(TracedDepth source) {
  switch (source) {
    case TracedDepth::kRaster: return "raster";
    case TracedDepth::kSplat: return "splat";
  }
  return "?";
}

}  // namespace dhr::client
