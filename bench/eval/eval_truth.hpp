// The ground truth of a frame: visibility traced exactly for the displayed views and shaded by the client's own
// pipeline (the paper's warp at identity), for `dhr-eval run`'s metrics and `dhr-eval compare`'s pictures.
#pragma once
#include "metrics/image_metrics.hpp"
#include "eval_render.hpp"
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "visibility/visibility.hpp"
#include "trace/visibility_tracer.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace dhr::eval {

struct Truth {
  std::array<std::vector<uint8_t>, 2> rgba;  // display-sized sRGB bytes
  std::array<LumaImage, 2> luma;
  std::array<VisibilityBuffer, 2> mask;
};

// Traced with the guard band the compared frames were traced with (only the display region is used): a camera
// with another guard band computes its ray directions with other rounding, which can flip a silhouette pixel.
Truth ground_truth(server::VisibilityTracer& tracer, EyeRenderer& renderer, Extent eye_size, GuardBand guard,
                   const std::array<View, 2>& views);

}  // namespace dhr::eval
