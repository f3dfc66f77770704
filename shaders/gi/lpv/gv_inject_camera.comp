#version 460
// Geometry volume from the camera G-buffer (body: gv_inject.glsl).
#extension GL_GOOGLE_include_directive : require
#define SURFEL_ARRAY 0
#include "gv_inject.glsl"
