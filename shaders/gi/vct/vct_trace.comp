#version 460
#extension GL_GOOGLE_include_directive : require
// Per-pixel cones at every f-th pixel (f = 1: every pixel).
#include "vct_trace_body.glsl"
