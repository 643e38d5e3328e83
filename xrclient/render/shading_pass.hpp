// Shading pass, compute, one eye:
//   I = albedo / pi * sum_i k_i * saturate(dot(N, L_i)) * E_i
// over the scene's point, spot and directional lights (shaders/light_eval.h, the same "contributes" test as
// the server), k_i = bit i of the predicted mask. Display encoding (shaders/display_encode.h):
// exposure, ACES filmic approximation, sRGB transfer function; written as bytes to an R8G8B8A8_UNORM storage
// image. Those bytes are sRGB-encoded: copy them (vkCmdCopyImage, not a blit) into an _SRGB swapchain image,
// or into a _UNORM one, and they display as computed (B8G8R8A8 swapchains: ShadingSettings::swap_red_blue). Debug views (ShadingView) replace the shaded colour.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "scene/light_slots.hpp"
#include "scene/scene.hpp"
#include "render/pass_util.hpp"
#include "render/warp_pass.hpp"
#include "vk/buffer.hpp"
#include "vk/handle.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

struct GBuffer;

inline constexpr VkFormat kShadingOutputFormat = VK_FORMAT_R8G8B8A8_UNORM;

// Values equal shader_interface.h's kClientView* constants.
enum class ShadingView : uint32_t {
  kShaded = 0,
  kLightVisibility = 1,  // ShadingSettings::debug_light: white lit, black shadowed, red unknown
  kUnknown = 2,          // shaded, unknown surface pixels tinted magenta
  kAlbedo = 3,
  kNormal = 4,
  kMotion = 5,           // needs warp motion vectors
};

// The optional warp outputs a view reads (light visibility and unknown: status; motion: motion vectors).
WarpOutputs warp_outputs_for(ShadingView view);
// Whether `targets` has what `view` reads.
bool debug_outputs_available(ShadingView view, const WarpTargets& targets);

struct ShadingSettings {
  float exposure = 1.0f;  // linear scale of the radiance before the tonemap
  ShadingView view = ShadingView::kShaded;
  uint32_t debug_light = 0;
  glm::vec3 background{0.02f, 0.02f, 0.025f};  // display-referred linear colour where there is no surface
  // Store the bytes as B, G, R: for a raw copy into a B8G8R8A8 swapchain image (the output stays an
  // R8G8B8A8_UNORM image; PNGs of it then show red and blue swapped).
  bool swap_red_blue = false;
};

// R8G8B8A8_UNORM, usage STORAGE | SAMPLED | TRANSFER_SRC.
vk::Image create_shading_output(const vk::Context& context, Extent extent);

class ShadingPass {
 public:
  // With `light_slots` (more than 32 lights, scene/light_slots.hpp; copied), the mask's fields are those slots and
  // record() takes every light of the scene, shading each field with the light its slot holds where the pixel's
  // surface is; null or the identity: field i is light i.
  explicit ShadingPass(const vk::Context& context, uint32_t slots = 1, const LightSlots* light_slots = nullptr);

  // Writes the lights (packed relative to the eye, in double) into the slot's buffer (the GPU must have
  // finished the slot's previous use) and records the pass. The G-buffer must be in SHADER_READ_ONLY_OPTIMAL
  // and the warp targets in GENERAL (as their passes leave them); `output` ends in GENERAL with its
  // writes visible to later shaders and transfers. Throws std::invalid_argument for mismatched sizes,
  // more lights than the fields hold (kMaxLights without light slots, the slots' light count with them), a bad slot,
  // or a debug view whose warp outputs are placeholders.
  void record(VkCommandBuffer cmd, uint32_t slot, GBuffer& gbuffer, WarpTargets& warp,
              const Camera& display, double near_plane, std::span<const SceneLight> lights,
              const ShadingSettings& settings, vk::Image& output);

  uint32_t slots() const { return static_cast<uint32_t>(slots_.size()); }

 private:
  struct Slot {
    vk::Buffer lights;
    VkDescriptorSet set = VK_NULL_HANDLE;
  };
  const vk::Context* context_;
  ComputePassCore core_;
  std::vector<Slot> slots_;
  std::optional<LightSlots> light_slots_;  // set: fields are light slots
  vk::Buffer light_slot_table;              // LightSlots::gpu_words (a header alone without slots)
};

}  // namespace dhr::render
