// --warp: which warp rule the eyes use (render::WarpSettings is made from it in the client's setup). Vulkan-free,
// so the shipped defaults (plan/shipped_defaults.hpp), dhr-eval and client_bench can name it.
#pragma once

namespace dhr::client {

enum class WarpChoice {
  kPaper,  // the paper's warp (unknown pixels lit)
  kFull,   // render::WarpSettings::full() (deferred, with shadow maps)
  kEdges,       // render::WarpSettings::server_edges() (forward, shadow maps where the samples disagree)
  kEdgesDepth,  // render::WarpSettings::server_edges_depth(--depth-scale) (the same plus the depth test)
  kAuto,        // kEdgesDepth where the scene has a light with an extent (soft levels), else kEdges: resolve_warp
};

inline const char* to_string(WarpChoice choice) {
  switch (choice) {
    case WarpChoice::kPaper: return "paper";
    case WarpChoice::kFull: return "full";
    case WarpChoice::kEdges: return "edges";
    case WarpChoice::kEdgesDepth: return "edges-depth";
    case WarpChoice::kAuto: return "auto";
  }
  return "?";
}

// The warp a choice takes in a scene: kAuto is kEdgesDepth where a light has an extent (its soft levels are blended
// across samples, and the depth test keeps an occluder's levels off the surfaces it uncovers) and kEdges where every
// light is hard (the edge band already gives the shadow maps the bits near a traced edge, and the depth test changes
// no measured bit there: docs/evaluation.md, "Disocclusion without a second raster pass"); the others are themselves.
inline WarpChoice resolve_warp(WarpChoice choice, bool scene_has_soft_lights) {
  if (choice != WarpChoice::kAuto) return choice;
  return scene_has_soft_lights ? WarpChoice::kEdgesDepth : WarpChoice::kEdges;
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
