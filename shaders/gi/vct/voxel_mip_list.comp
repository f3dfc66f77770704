#version 460
#extension GL_GOOGLE_include_directive : require
// Level 1 of the directional volume from level 0 at the listed occupied 2^3 blocks only (the
// others stay 0).
#define GI_VOXEL_MIP_LIST
#include "voxel_mip_body.glsl"
