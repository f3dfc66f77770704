#version 460
#extension GL_GOOGLE_include_directive : require
// Fixed-point accumulation -> albedo/normal/emission volumes.
#include "voxel_resolve_body.glsl"
