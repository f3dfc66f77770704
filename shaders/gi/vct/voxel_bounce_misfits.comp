#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, the misfit voxels, within the grid (voxel_bounce_misfits_body.glsl).
#include "voxel_bounce_misfits_body.glsl"
