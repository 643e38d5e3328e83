#version 460
#extension GL_GOOGLE_include_directive : require
// The forward pass with colour and status (the paper's warp): client/forward_body.h.
#define DHR_FORWARD_STATUS 1
#define DHR_FORWARD_MASK 0
#include "client/forward_body.h"
