#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/shader_interface.h"
#include "client/mesh_position.h"

// The shadow maps' vertices (render/shadow_maps.cpp; depth only, no fragment shader): the position alone, read
// from the positions' stream alone (render::ClientScene::position_bindings), as gbuffer.vert places it.
layout(location = 0) in vec3 in_position;

layout(push_constant, std430) uniform Push { ClientGBufferPush pc; };

void main() { gl_Position = mesh_clip_position(pc, in_position); }
