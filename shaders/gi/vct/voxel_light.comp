#version 460
#extension GL_GOOGLE_include_directive : require
// Voxel direct light, occlusion ray-marched through the occupancy, hard (first occupied voxel).
#include "voxel_light_body.glsl"
