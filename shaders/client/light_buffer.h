// The client's lights (GLSL): PackedLight[] (shaders/light_eval.h), positions relative to the display eye in world
// axes, read by client/shade.h and client/shadow_lookup.h. Declared here rather than passed because GLSL cannot
// pass a runtime-sized buffer to a function and both helpers loop over it.
// Before including this (or a header that includes it), the shader defines
//   DHR_LIGHT_BUFFER_SET, DHR_LIGHT_BUFFER_BINDING: the descriptor set and binding of its PackedLight[] buffer.
#ifndef DHR_LIGHT_BUFFER_H
#define DHR_LIGHT_BUFFER_H

#if !defined(DHR_LIGHT_BUFFER_SET) || !defined(DHR_LIGHT_BUFFER_BINDING)
#error "define DHR_LIGHT_BUFFER_SET and DHR_LIGHT_BUFFER_BINDING before including client/light_buffer.h"
#endif

#include "shaders/light_eval.h"

layout(set = DHR_LIGHT_BUFFER_SET, binding = DHR_LIGHT_BUFFER_BINDING, std430) readonly buffer Lights {
  PackedLight lights[];
};

#endif  // DHR_LIGHT_BUFFER_H
