#version 460
#extension GL_GOOGLE_include_directive : require
// First anisotropic level, from the isotropic radiance volume.
#define GI_VOXEL_MIP_FROM_RADIANCE
#include "voxel_mip_body.glsl"
