#version 460
#extension GL_GOOGLE_include_directive : require
// The forward pass with colour, status and mask (tests, dhr-eval): client/forward_body.h.
#define DHR_FORWARD_STATUS 1
#define DHR_FORWARD_MASK 1
#include "client/forward_body.h"
