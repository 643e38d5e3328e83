// What dhr-xrclient does when no option says otherwise. Its command line starts from these values and dhr-eval's
// `default` method runs them (DESIGN 8b: what ships by default is what is measured), so a default changes here,
// once, for both.
#pragma once
#include "math/projection.hpp"
#include "plan/render_path.hpp"
#include "plan/schedule.hpp"
#include "plan/warp_choice.hpp"

#include <cstdint>

namespace dhr::client::shipped {

inline constexpr Schedule kSchedule = Schedule::kNewest;  // --schedule
inline constexpr uint32_t kXMax = 3;                      // --x-max (the paper schedule only)
// --warp: edges, plus the depth test in scenes with soft lights (resolve_warp).
inline constexpr WarpChoice kWarp = WarpChoice::kAuto;
// --depth-scale (edges-depth, full): the depth test's traced depth at the traced resolution.
inline constexpr uint32_t kDepthScale = 1;
// --traced-depth (edges-depth, full): the traced depth splatted from the eye's previous frame, no raster pass.
inline constexpr TracedDepth kTracedDepth = TracedDepth::kSplat;
// --edge-band (edges, edges-depth, full): a hard light's bit any traced pixel within 3 pixels of a used sample
// disagrees on takes the shadow maps (render::WarpSettings::edge_band; docs/client.md "Warp rule").
inline constexpr uint32_t kEdgeBand = 3;
// --shadow-fill-period-ms: in a moving scene, while the client's shadow maps only fill the warp's unknown bits,
// each light's map is re-rendered every 2 frames at 90 Hz, in turns (render::ShadowRefresh; docs/motion.md "Cost").
inline constexpr int64_t kShadowFillPeriodNs = 22'222'222;
inline constexpr RenderPath kRenderPath = RenderPath::kAuto;  // --render-path (forward_pass_for: the device decides)
// --guard: the paper's +64x36 at 1920x1080, scaled to the eye size.
inline GuardBand guard_band(Extent eye) { return paper_guard_band(eye); }

}  // namespace dhr::client::shipped
