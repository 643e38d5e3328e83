#version 460
#extension GL_GOOGLE_include_directive : require
// The forward pass with colour only (Lambert, shadow maps): client/forward_body.h.
#define DHR_FORWARD_STATUS 0
#define DHR_FORWARD_MASK 0
#include "client/forward_body.h"
