// The ground truth of a frame: visibility traced at the displayed views and shaded by the client's own pipeline
// (the paper's warp at identity), for `dhr-eval run`'s metrics and `dhr-eval compare`'s pictures.
//
// Per pixel and light the exact share k of the light the surface point sees (trace/soft's trace_soft_image):
// a punctual light's one ray (the hard tracer's bit), a light with an extent sampled with TruthSampling's samples
// (truth_sampling.hpp), scrambled independently of the server's sampling (another salt). The picture
// shades that k unquantized (exact_shading.hpp); the masks hold the levels nearest to it.
#pragma once
#include "metrics/image_metrics.hpp"
#include "eval_render.hpp"
#include "truth_sampling.hpp"
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "scene/scene.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "visibility/visibility.hpp"
#include "visibility/visibility_layout.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace dhr::eval {

// One eye's exact visibility in the display region (the guard band cropped away).
struct ExactVisibility {
  uint32_t width = 0, height = 0, lights = 0;
  std::vector<float> fraction;   // (y * width + x) * lights + light
  std::vector<uint8_t> surface;  // y * width + x: 1 where the primary ray hit a surface
};

struct Truth {
  std::array<std::vector<uint8_t>, 2> rgba;  // display-sized sRGB bytes, shaded with the exact fractions
  std::array<LumaImage, 2> luma;
  std::array<VisibilityBuffer, 2> mask;      // the nearest levels (layout bits), as the pipeline read them back
  std::array<ExactVisibility, 2> exact;
};

// What the truth traces: the run's Embree tracer (its scene, moved to the display's scene time before each truth)
// and the scene's lights at rest (at most kMaxLights, the layout's), moved with light_at. With more lights
// (light_slots; hard lights only, a static scene) the fields are the slots the lights share: the truth is the
// tracer's exhaustive trace of them (one ray per pair is exact for a point light), each field's k its bit.
struct TruthScene {
  server::EmbreeTracer* tracer = nullptr;
  const Scene* scene = nullptr;  // the loaded scene (its animation moves the lights)
  std::span<const SceneLight> lights;
  VisibilityLayout layout;  // render::layout_for_lights of `lights` (of the field lights with slots), as the client
  bool light_slots = false;
};

// The truth of the frame `pose` displays: traced at its views and at its scene time (the scene and its lights as
// they are at pose.scene_time_ns; a static scene is the same at every time).
// Traced with the guard band the compared frames were traced with (only the display region is used): a camera
// with another guard band computes its ray directions with other rounding, which can flip a silhouette pixel.
Truth ground_truth(const TruthScene& scene, const TruthSampling& sampling, EyeRenderer& renderer, Extent eye_size,
                   GuardBand guard, const FramePose& pose);

}  // namespace dhr::eval
