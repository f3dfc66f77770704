#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, gather half, within the grid (voxel_bounce_body.glsl).
#include "voxel_bounce_body.glsl"
