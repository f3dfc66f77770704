#version 460
#extension GL_GOOGLE_include_directive : require
// Level k of the directional volume from level k - 1 of the same directions.
#include "voxel_mip_body.glsl"
