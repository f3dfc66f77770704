#version 460
#extension GL_GOOGLE_include_directive : require
// Voxel direct light, occlusion from the direct-light shadow atlas (VctOcclusion::ShadowMap).
#define GI_VOXEL_LIGHT_SHADOW_MAP
#include "voxel_light_body.glsl"
