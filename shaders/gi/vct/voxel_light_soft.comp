#version 460
#extension GL_GOOGLE_include_directive : require
// Voxel direct light, occlusion ray-marched through the trilinear occupancy (VctOcclusion::RayMarchSoft).
#define GI_VOXEL_LIGHT_SOFT
#include "voxel_light_body.glsl"
