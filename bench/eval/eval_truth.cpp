#include "eval_truth.hpp"

#include "exact_shading.hpp"
#include "trace/soft/soft_image.hpp"
#include "visibility/soft_levels.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dhr::eval {
namespace {

constexpr float kTopLevel = static_cast<float>(kDefaultSoftLevels - 1);

// (levels - 1) x k minus the level nearest k, in [-0.5, 0.5]: the way to the neighbouring level toward k and how
// far along it k lies.
float level_offset(float k) { return k * kTopLevel - static_cast<float>(quantize(k, kDefaultSoftLevels)); }

// Every light at the level nearest its fraction (a hard light's bit); `step_light` (>= 0) one level toward its
// fraction instead, where that is not on a level.
VisibilityBuffer level_masks(const server::SoftImage& image, const VisibilityLayout& layout, int step_light) {
  VisibilityBuffer out = VisibilityBuffer::create(image.width, image.height, layout.total_bits());
  for (size_t p = 0; p < out.pixel_count(); ++p) {
    uint32_t mask = 0;
    for (uint32_t l = 0; l < layout.light_count; ++l) {
      float k = image.fraction[p * image.lights + l];
      if (static_cast<int>(l) == step_light) {
        const float offset = level_offset(k);
        const float level = static_cast<float>(quantize(k, kDefaultSoftLevels));
        k = (level + (offset > 0.0f ? 1.0f : offset < 0.0f ? -1.0f : 0.0f)) / kTopLevel;
      }
      mask = layout.with_visibility(mask, l, k);
    }
    out.set_mask_at(p, mask);
  }
  return out;
}

ExactVisibility crop_display(const server::SoftImage& image, Extent eye, GuardBand guard) {
  ExactVisibility e;
  e.width = eye.width;
  e.height = eye.height;
  e.lights = image.lights;
  e.fraction.resize(size_t{eye.width} * eye.height * image.lights);
  e.surface.resize(size_t{eye.width} * eye.height);
  for (uint32_t y = 0; y < eye.height; ++y) {
    for (uint32_t x = 0; x < eye.width; ++x) {
      const size_t to = size_t{y} * eye.width + x;
      const size_t from = size_t{y + guard.y} * image.width + x + guard.x;
      e.surface[to] = image.surface[from];
      std::copy_n(image.fraction.begin() + static_cast<std::ptrdiff_t>(from * image.lights), image.lights,
                  e.fraction.begin() + static_cast<std::ptrdiff_t>(to * image.lights));
    }
  }
  return e;
}

// Light slots: each hard field's bit as its fraction, in `image` (whose surfaces a trace without lights found).
void fields_as_fractions(const VisibilityBuffer& masks, const VisibilityLayout& layout, server::SoftImage& image) {
  image.lights = layout.light_count;
  image.fraction.assign(masks.pixel_count() * layout.light_count, 0.0f);
  for (size_t p = 0; p < masks.pixel_count(); ++p)
    for (uint32_t l = 0; l < layout.light_count; ++l)
      image.fraction[p * layout.light_count + l] = layout.visibility(masks.mask_at(p), l);
}

// Per display pixel: how far light `light`'s exact fraction lies from its nearest level toward the stepped one.
std::vector<float> step_weights(const ExactVisibility& exact, uint32_t light) {
  std::vector<float> w(exact.surface.size());
  for (size_t p = 0; p < w.size(); ++p) w[p] = std::fabs(level_offset(exact.fraction[p * exact.lights + light]));
  return w;
}

}  // namespace

Truth ground_truth(const TruthScene& scene, const TruthSampling& sampling, EyeRenderer& renderer, Extent eye_size,
                   GuardBand guard, const FramePose& pose) {
  const std::array<View, 2>& views = pose.views;
  const double scene_time = static_cast<double>(pose.scene_time_ns) * 1e-9;
  // The service traces its frames on the same tracer, each at its own scene time: move it to the display's.
  scene.tracer->set_scene_time(scene_time);
  std::vector<SceneLight> lights(scene.lights.begin(), scene.lights.end());
  for (SceneLight& light : lights) light = light_at(*scene.scene, light, scene_time);
  server::SoftImageOptions options;
  options.sampling =
      server::SoftOptions{sampling.first_samples, sampling.samples, sampling.salt, server::SoftPattern::kPerPixel};
  options.threads = sampling.threads;
  Truth truth;
  std::array<server::SoftImage, 2> images;
  std::array<Camera, 2> cameras;
  std::array<VisibilityBuffer, 2> slot_masks;  // with light slots: the exhaustive trace of the fields
  for (int eye = 0; eye < 2; ++eye) {
    cameras[eye] = Camera::with_guard_band(views[eye], eye_size, guard);
    if (scene.light_slots) {
      // The surfaces from a trace without lights, the fields' bits from the tracer.
      server::trace_soft_image(scene.tracer->embree_scene(), {}, cameras[eye], options, images[eye]);
      server::TraceStats stats;
      scene.tracer->trace_layout(cameras[eye], scene.layout, slot_masks[eye], stats);
      fields_as_fractions(slot_masks[eye], scene.layout, images[eye]);
    } else {
      server::trace_soft_image(scene.tracer->embree_scene(), lights, cameras[eye], options, images[eye]);
    }
    truth.exact[eye] = crop_display(images[eye], eye_size, guard);
  }
  std::array<VisibilityBuffer, 2> buffers;
  const auto render = [&](int step_light) {
    std::array<VisibilityInput, 2> inputs;
    for (int eye = 0; eye < 2; ++eye) {
      buffers[eye] = scene.light_slots ? slot_masks[eye] : level_masks(images[eye], scene.layout, step_light);
      inputs[eye].buffer = &buffers[eye];
      inputs[eye].traced = cameras[eye];
      inputs[eye].scene_time_ns = pose.scene_time_ns;
    }
    return renderer.render(views, inputs, pose.scene_time_ns);  // the paper's warp at identity
  };
  std::array<EyeRender, 2> base = render(-1);
  std::array<RadianceSum, 2> sums{RadianceSum(base[0].rgba), RadianceSum(base[1].rgba)};
  for (uint32_t light = 0; light < scene.layout.light_count; ++light) {
    if (!scene.layout.is_soft(light)) continue;
    const std::array<std::vector<float>, 2> weights{step_weights(truth.exact[0], light),
                                                    step_weights(truth.exact[1], light)};
    const auto off_level = [](const std::vector<float>& w) {
      return std::any_of(w.begin(), w.end(), [](float v) { return v > 0.0f; });
    };
    if (!off_level(weights[0]) && !off_level(weights[1])) continue;
    const std::array<EyeRender, 2> stepped = render(static_cast<int>(light));
    for (int eye = 0; eye < 2; ++eye) sums[eye].add_step(stepped[eye].rgba, weights[eye]);
  }
  for (int eye = 0; eye < 2; ++eye) {
    truth.rgba[eye] = sums[eye].encode();
    truth.luma[eye] = luma_from_rgba8(truth.rgba[eye], eye_size.width, eye_size.height);
    truth.mask[eye] = std::move(base[eye].mask);
  }
  return truth;
}

}  // namespace dhr::eval
