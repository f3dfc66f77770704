#version 460
#extension GL_GOOGLE_include_directive : require
// Per-pixel cones for the pixels of the refine list (full resolution).
#define GI_VCT_REFINE
#include "vct_trace_body.glsl"
