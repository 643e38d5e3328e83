#include "render/warp_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dhr::render {
namespace {

// Distance of coordinate v from the nearest integer (the pixel boundaries).
double boundary_distance(double v) { return std::abs(v - std::round(v)); }

// How far (px) the inside/outside and floor decisions are from flipping.
double lookup_margin(const glm::dvec2& p, const Extent& extent) {
  const double w = extent.width, h = extent.height;
  const double out_x = p.x < 0.0 ? -p.x : (p.x >= w ? p.x - w : -1.0);
  const double out_y = p.y < 0.0 ? -p.y : (p.y >= h ? p.y - h : -1.0);
  if (out_x >= 0.0 || out_y >= 0.0) return std::max(out_x, out_y);  // outside: only the edge distance counts
  return std::min(boundary_distance(p.x), boundary_distance(p.y));
}

}  // namespace

const char* to_string(WarpStatus status) {
  switch (status) {
    case WarpStatus::kKnown: return "known";
    case WarpStatus::kBackground: return "background";
    case WarpStatus::kBehind: return "behind";
    case WarpStatus::kOutside: return "outside";
    case WarpStatus::kMissingRow: return "missing_row";
    case WarpStatus::kNoData: return "no_data";
  }
  return "?";
}

uint64_t WarpCounts::unknown_surface() const {
  return (*this)[WarpStatus::kBehind] + (*this)[WarpStatus::kOutside] + (*this)[WarpStatus::kMissingRow] +
         (*this)[WarpStatus::kNoData];
}

uint64_t WarpCounts::surface() const { return unknown_surface() + (*this)[WarpStatus::kKnown]; }

uint32_t unknown_mask(const VisibilityBuffer* visibility) {
  return visibility != nullptr ? visibility->light_bits() : 0xFFFFFFFFu;
}

std::optional<std::string> validate_visibility_input(const Camera& traced, const VisibilityBuffer& visibility,
                                                     std::span<const uint8_t> row_valid) {
  if (auto err = validate_camera(traced)) return "traced camera: " + *err;
  if (traced.extent.width != visibility.width || traced.extent.height != visibility.height) {
    return "visibility buffer is " + std::to_string(visibility.width) + "x" + std::to_string(visibility.height) +
           " but its traced camera is " + std::to_string(traced.extent.width) + "x" +
           std::to_string(traced.extent.height);
  }
  if (visibility.width == 0 || visibility.height == 0 || visibility.width > kMaxBufferDimension ||
      visibility.height > kMaxBufferDimension) {
    return "visibility buffer size " + std::to_string(visibility.width) + "x" + std::to_string(visibility.height) +
           " is empty or exceeds " + std::to_string(kMaxBufferDimension);
  }
  if (visibility.light_count > kMaxLights) return "visibility buffer has more than 32 lights";
  if (!mask_width_from_bits(static_cast<uint32_t>(visibility.mask_bits))) return "visibility buffer mask width";
  if (visibility.data.size() != visibility.size_bytes()) {
    return "visibility buffer holds " + std::to_string(visibility.data.size()) + " bytes, expected " +
           std::to_string(visibility.size_bytes());
  }
  if (!row_valid.empty() && row_valid.size() != visibility.height) {
    return "row validity has " + std::to_string(row_valid.size()) + " entries for " +
           std::to_string(visibility.height) + " rows";
  }
  return std::nullopt;
}

WarpResult warp_reference(const WarpInput& input) {
  if (auto err = validate_camera(input.display)) throw std::invalid_argument("display camera: " + *err);
  const Extent extent = input.display.extent;
  if (input.depth.size() != size_t{extent.width} * extent.height) {
    throw std::invalid_argument("warp reference: depth has " + std::to_string(input.depth.size()) +
                                " values for a " + std::to_string(extent.width) + "x" +
                                std::to_string(extent.height) + " camera");
  }
  if (input.visibility != nullptr) {
    if (auto err = validate_visibility_input(input.traced, *input.visibility, input.row_valid)) {
      throw std::invalid_argument("warp reference: " + *err);
    }
  }
  const size_t n = input.depth.size();
  WarpResult out;
  out.extent = extent;
  out.masks.assign(n, unknown_mask(input.visibility));
  out.status.assign(n, WarpStatus::kKnown);
  out.lookup.assign(n, glm::dvec2(0.0));
  out.margin.assign(n, std::numeric_limits<double>::infinity());

  for (uint32_t y = 0; y < extent.height; ++y) {
    for (uint32_t x = 0; x < extent.width; ++x) {
      const size_t i = size_t{y} * extent.width + x;
      WarpStatus& status = out.status[i];
      const double d = input.depth[i];
      if (!(d > 0.0)) {
        status = WarpStatus::kBackground;
      } else if (input.visibility == nullptr) {
        status = WarpStatus::kNoData;
      } else {
        const glm::dvec3 p = world_point_from_depth(input.display, input.near_plane, x + 0.5, y + 0.5, d);
        const Reprojection r = reproject(input.traced, p, input.min_depth);
        // A depth within 1e-6 m of the threshold may be decided either way in float.
        const double depth_margin = std::abs(r.depth - input.min_depth) * 1e6;
        if (r.status == Reprojection::Status::kBehind) {
          status = WarpStatus::kBehind;
          out.margin[i] = depth_margin;
        } else {
          out.lookup[i] = r.pixel;
          out.margin[i] = std::min(depth_margin, lookup_margin(r.pixel, input.traced.extent));
          if (r.status == Reprojection::Status::kOutside) {
            status = WarpStatus::kOutside;
          } else {
            const auto ix = static_cast<uint32_t>(std::floor(r.pixel.x));
            const auto iy = static_cast<uint32_t>(std::floor(r.pixel.y));
            if (!input.row_valid.empty() && input.row_valid[iy] == 0) {
              status = WarpStatus::kMissingRow;
            } else {
              out.masks[i] = input.visibility->get(ix, iy);
            }
          }
        }
      }
      ++out.counts.by_status[static_cast<size_t>(status)];
    }
  }
  return out;
}

}  // namespace dhr::render
