#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
// Level 1 of the directional volume from level 0 at the listed occupied 2^3 blocks, and the
// second bounce's job list from their voxels' normal classes (voxel_mip_body.glsl,
// gi/vct_passes.h).
#define GI_VOXEL_MIP_LIST
#define GI_VOXEL_MIP_JOBS
#include "voxel_mip_body.glsl"
