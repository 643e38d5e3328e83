#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"

// G-buffer: world-space unit normal (flipped on back faces: only double-sided materials draw them) and
// linear albedo = base colour factor x texture (the sRGB image format decodes the texels).
layout(set = 0, binding = kClientGBufferBindingBaseColor) uniform sampler2D base_color_texture;
layout(push_constant, std430) uniform Push { ClientGBufferPush pc; };

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec2 in_uv;

layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;

void main() {
  const vec4 factor = vec4(pc.base_color_r, pc.base_color_g, pc.base_color_b, pc.base_color_a);
  const vec4 base = texture(base_color_texture, in_uv) * factor;
  if ((pc.flags & kClientMaterialAlphaMask) != 0u && base.a < pc.alpha_cutoff) discard;
  const float len2 = dot(in_normal, in_normal);
  // Interpolating opposite vertex normals can give ~0: fall back to +Y instead of a NaN.
  vec3 n = len2 > 1e-20 ? in_normal * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
  if (!gl_FrontFacing) n = -n;
  out_normal = vec4(n, 1.0);
  out_albedo = vec4(clamp(base.rgb, 0.0, 1.0), 1.0);
}
