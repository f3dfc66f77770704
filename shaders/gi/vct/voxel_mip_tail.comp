#version 460
#extension GL_GOOGLE_include_directive : require
// The coarsest levels of the directional volume (from 8^3 down to 1^3) in one work group.
#define GI_VOXEL_MIP_TAIL
#include "voxel_mip_body.glsl"
