// visibility_error: the mean over surface pixels and lights of |k shown - k exact|, k shown what the client shades
// with (a hard light's bit, a soft light's level / 7, read from the displayed masks in their layout, or the warp's
// refined share of it where there is one: render/soft_refine.hpp), k exact the truth's fraction (a hard light's
// bit). With hard lights only it counts the wrong bits of surface pixels.
#pragma once
#include "eval_truth.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dhr::eval {

struct VisibilityError {
  uint64_t surface_pixels = 0;
  std::vector<double> per_light;  // sum over surface pixels of |k shown - k exact|
  // Mean over surface pixels and lights (0 without any); light_mean: one light's.
  double mean() const;
  double light_mean(uint32_t light) const;
};

// std::nullopt when `shown` is not display-sized in `layout`, the light counts differ, or `soft` (the refined
// shares per pixel; empty: none) is neither empty nor one per pixel.
std::optional<VisibilityError> visibility_error(const VisibilityBuffer& shown, const VisibilityLayout& layout,
                                                const ExactVisibility& exact, std::span<const uint32_t> soft = {});

}  // namespace dhr::eval
