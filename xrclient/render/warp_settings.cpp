// WarpSettings and the warp's status names and counts (declared in render/warp_reference.hpp): which ingredients a
// --warp choice turns on, apart from the reference rule that applies them (warp_reference.cpp).
#include "render/warp_reference.hpp"

#include <stdexcept>

namespace dhr::render {

const char* to_string(WarpStatus status) {
  switch (status) {
    case WarpStatus::kKnown: return "known";
    case WarpStatus::kBackground: return "background";
    case WarpStatus::kBehind: return "behind";
    case WarpStatus::kOutside: return "outside";
    case WarpStatus::kMissingRow: return "missing_row";
    case WarpStatus::kNoData: return "no_data";
    case WarpStatus::kDisoccluded: return "disoccluded";
  }
  return "?";
}

uint64_t WarpCounts::unknown_surface() const {
  return (*this)[WarpStatus::kBehind] + (*this)[WarpStatus::kOutside] + (*this)[WarpStatus::kMissingRow] +
         (*this)[WarpStatus::kNoData] + (*this)[WarpStatus::kDisoccluded];
}

WarpSettings warp_settings_for(client::WarpChoice choice, uint32_t depth_scale, uint32_t edge_band,
                               client::TracedDepth traced_depth) {
  WarpSettings s;
  switch (choice) {
    case client::WarpChoice::kPaper: return s;
    case client::WarpChoice::kFull:
      s = WarpSettings::full();
      s.depth_scale = depth_scale;
      s.edge_band = edge_band;
      break;
    case client::WarpChoice::kEdges: return WarpSettings::server_edges(edge_band);
    case client::WarpChoice::kEdgesDepth: s = WarpSettings::server_edges_depth(depth_scale, edge_band); break;
    case client::WarpChoice::kAuto:
      throw std::invalid_argument("warp_settings_for: --warp auto is resolved with the scene (resolve_warp) first");
  }
  s.depth_splat = traced_depth == client::TracedDepth::kSplat;
  return s;
}

WarpSettings WarpSettings::full() {
  WarpSettings s;
  s.bilinear = s.depth_test = s.other_eye = s.shadow_fill = s.shadow_edges = s.shadow_first = true;
  s.older_buffer = s.neighbour_fill = s.motion = s.soft_refine = true;
  s.edge_band = client::shipped::kEdgeBand;
  return s;
}

WarpSettings WarpSettings::server_edges(uint32_t edge_band) {
  WarpSettings s;
  s.bilinear = s.shadow_edges = s.shadow_fill = s.motion = s.soft_refine = true;
  s.edge_band = edge_band;
  return s;
}

WarpSettings WarpSettings::server_edges_depth(uint32_t depth_scale, uint32_t edge_band) {
  WarpSettings s = server_edges(edge_band);
  s.depth_test = true;
  s.depth_scale = depth_scale;
  return s;
}

bool WarpSettings::is_server_edges() const {
  WarpSettings plain = *this;
  plain.depth_test = false;
  plain.depth_scale = 1;
  plain.depth_splat = false;
  plain.soft_refine = true;  // either way: the forward pass refines as the compute warp does
  plain.plane_tolerance_rel = server_edges().plane_tolerance_rel;
  plain.plane_tolerance_abs = server_edges().plane_tolerance_abs;
  return plain == server_edges(edge_band);
}

}  // namespace dhr::render
