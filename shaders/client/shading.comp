#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"
#include "shaders/display_encode.h"
#include "client/float3.h"

// Shading: I = albedo / pi * sum_i k_i * saturate(N.L_i) * E_i, with k_i light i's field of the predicted mask
// (client/visibility_field.h: the bit, or a soft light's level / 7, or the warp's refined share of it) and the
// light math of light_eval.h (the server's notion of "contributes"). Positions are eye-relative (world axes):
// the surface point from depth, the lights packed relative to the eye in double on the CPU.
// Output: exposure -> ACES approximation -> sRGB encoding, stored as bytes in an RGBA8_UNORM image.
layout(local_size_x = kClientWarpGroupSize, local_size_y = kClientWarpGroupSize) in;

layout(set = 0, binding = kClientShadingBindingDepth) uniform sampler2D depth_texture;
layout(set = 0, binding = kClientShadingBindingNormal) uniform sampler2D normal_texture;
layout(set = 0, binding = kClientShadingBindingAlbedo) uniform sampler2D albedo_texture;
layout(set = 0, binding = kClientShadingBindingMask, r32ui) uniform readonly uimage2D mask_image;
layout(set = 0, binding = kClientShadingBindingStatus, r32ui) uniform readonly uimage2D status_image;
layout(set = 0, binding = kClientShadingBindingMotion, rg32f) uniform readonly image2D motion_image;
layout(set = 0, binding = kClientShadingBindingOutput, rgba8) uniform writeonly image2D output_image;
layout(set = 0, binding = kClientShadingBindingSoft, r32ui) uniform readonly uimage2D soft_image;
layout(push_constant, std430) uniform Push { ClientShadingPush pc; };
// The lights are declared by the helper (client/light_buffer.h, through shade.h).
#define DHR_LIGHT_BUFFER_SET 0
#define DHR_LIGHT_BUFFER_BINDING kClientShadingBindingLights
#define DHR_LIGHT_SLOTS_BINDING kClientShadingBindingLightSlots
#include "client/shade.h"

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  if (id.x >= pc.width || id.y >= pc.height) return;
  const ivec2 pixel = ivec2(id);

  const float d = texelFetch(depth_texture, pixel, 0).r;
  const vec2 centre = vec2(id) + 0.5;
  const vec3 p = (pc.near_plane / d) * (v3(pc.ray0) + centre.x * v3(pc.ray_dx) + centre.y * v3(pc.ray_dy));
  const vec3 n = normalize(texelFetch(normal_texture, pixel, 0).xyz);
  const vec3 albedo = texelFetch(albedo_texture, pixel, 0).rgb;
  const uint mask = imageLoad(mask_image, pixel).x;
  // The warp's refined soft shares (kClientWarpSoftRefine), which replace those fields' levels.
  const uint refined =
      (pc.flags & kClientShadingSoftRefined) != 0u ? imageLoad(soft_image, pixel).x : kClientSoftRefineNoneAll;

  const vec3 radiance = (pc.flags & kClientShadingLightSlots) != 0u
                            ? shade_radiance_slots(p, n, albedo, mask, pc.light_count, pc.soft_lights,
                                                   v3(pc.slot_origin_mm))
                            : shade_radiance(p, n, albedo, mask, pc.light_count, pc.soft_lights, refined);
  vec3 display = encode_radiance(radiance, pc.exposure);

  if (pc.view_mode != kClientViewShaded) {
    const uint packed = imageLoad(status_image, pixel).x;
    const uint status = packed & 0xFFu;
    const uint fill = packed >> 8;
    if (pc.view_mode == kClientViewLightVisibility) {
      // A soft light: grey by its level (0.1 hidden .. 0.9 fully visible).
      uint offset = 0u;
      for (uint i = 0u; i < pc.debug_light; ++i) offset += field_bits(pc.soft_lights, i);
      const uint bits = field_bits(pc.soft_lights, pc.debug_light);
      const float grey = bits == 1u ? (((mask >> offset) & 1u) != 0u ? 0.9 : 0.1)
                                    : 0.1 + 0.8 * field_visibility(mask, offset, bits);
      display = status != kClientStatusKnown ? vec3(1.0, 0.0, 0.0) : vec3(grey);
    } else if (pc.view_mode == kClientViewUnknown) {
      // Unfilled (shaded lit): magenta; filled from the other eye: cyan; from the shadow maps: yellow.
      const vec3 tint = fill == kClientFillOtherEye ? vec3(0.0, 1.0, 1.0)
                      : fill == kClientFillShadowMap ? vec3(1.0, 1.0, 0.0) : vec3(1.0, 0.0, 1.0);
      if (status != kClientStatusKnown) display = mix(display, tint, 0.6);
    } else if (pc.view_mode == kClientViewAlbedo) {
      display = vec3(srgb_encode(albedo.x), srgb_encode(albedo.y), srgb_encode(albedo.z));
    } else if (pc.view_mode == kClientViewNormal) {
      display = n * 0.5 + 0.5;
    } else if (pc.view_mode == kClientViewMotion) {
      const vec2 motion = imageLoad(motion_image, pixel).xy;
      display = vec3(clamp(vec2(0.5) + motion / 32.0, 0.0, 1.0), 0.5);
    }
  }
  if (!(d > 0.0)) {
    const vec3 background = vec3(pc.background_r, pc.background_g, pc.background_b);
    display = vec3(srgb_encode(background.x), srgb_encode(background.y), srgb_encode(background.z));
  }
  if ((pc.flags & kClientShadingSwapRedBlue) != 0u) display = display.bgr;
  imageStore(output_image, pixel, vec4(display, 1.0));
}
