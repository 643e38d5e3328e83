// What dhr-server does when no option says otherwise. Its command line starts from these values and dhr-eval's
// `default` method runs them (DESIGN 8b: what ships by default is what is measured), so a default changes here,
// once, for both. ServiceConfig's own defaults stay the plain service (no prediction) for code that builds one.
#pragma once

namespace dhr::server::shipped {

// --predict / --no-predict: trace the views predicted for the display time. On since issue 25: with the paper warp
// it beat the poses as sent at every round trip measured (docs/evaluation.md, "paper+pred").
inline constexpr bool kPredict = true;
// --adaptive-fov: measured only with the full warp so far (docs/evaluation.md), so not yet shipped.
inline constexpr bool kAdaptiveFov = false;
// --reuse auto: reuse of earlier traces (trace/reuse) where it was measured to save time: the Embree tracer (the
// only one that reuses), soft levels on and a light with an extent, where it halved the trace time; with hard
// shadows only it cast fewer rays but took longer (docs/performance.md, "Reuse across frames and sessions").
inline constexpr bool reuse_by_default(bool embree, bool soft_levels, bool light_with_extent) {
  return embree && soft_levels && light_with_extent;
}

}  // namespace dhr::server::shipped
