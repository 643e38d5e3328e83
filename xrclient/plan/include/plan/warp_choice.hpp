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

}  // namespace dhr::client
