#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, gather half, of a clipmap level through the clipmap (voxel_bounce_body.glsl).
#define GI_VCT_CLIPMAP
#include "voxel_bounce_body.glsl"
