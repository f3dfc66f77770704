#version 460
// LPV propagation step on RGBA32F SH volumes (body: propagate.glsl).
#extension GL_GOOGLE_include_directive : require
#define LPV_FORMAT rgba32f
#include "propagate.glsl"
