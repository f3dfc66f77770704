#version 460
#extension GL_GOOGLE_include_directive : require
// Per-pixel cones at every f-th pixel through the clipmap (VctSettings::levels > 1).
#define GI_VCT_CLIPMAP
#include "vct_trace_body.glsl"
