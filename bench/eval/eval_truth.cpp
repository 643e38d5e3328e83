#include "eval_truth.hpp"

namespace dhr::eval {

Truth ground_truth(server::VisibilityTracer& tracer, EyeRenderer& renderer, Extent eye_size, GuardBand guard,
                   const std::array<View, 2>& views) {
  Truth truth;
  std::array<VisibilityBuffer, 2> exact;
  std::array<VisibilityInput, 2> inputs;
  for (int eye = 0; eye < 2; ++eye) {
    const Camera camera = Camera::with_guard_band(views[eye], eye_size, guard);
    server::TraceStats stats;
    tracer.trace(camera, exact[eye], stats);
    inputs[eye].buffer = &exact[eye];
    inputs[eye].traced = camera;
  }
  std::array<EyeRender, 2> renders = renderer.render(views, inputs);  // the paper's warp at identity
  for (int eye = 0; eye < 2; ++eye) {
    EyeRender& r = renders[eye];
    truth.luma[eye] = luma_from_rgba8(r.rgba, eye_size.width, eye_size.height);
    truth.rgba[eye] = std::move(r.rgba);
    truth.mask[eye] = std::move(r.mask);
  }
  return truth;
}

}  // namespace dhr::eval
