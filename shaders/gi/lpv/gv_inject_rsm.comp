#version 460
// Geometry volume from the RSM (body: gv_inject.glsl).
#extension GL_GOOGLE_include_directive : require
#define SURFEL_ARRAY 1
#include "gv_inject.glsl"
