#version 460
#extension GL_GOOGLE_include_directive : require
// Dynamic accumulation merged under the static volumes (static voxels win).
#define GI_VOXEL_MERGE
#include "voxel_resolve_body.glsl"
