#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, the misfit voxels of a clipmap level, through the clipmap.
#define GI_VCT_CLIPMAP
#include "voxel_bounce_misfits_body.glsl"
