#version 460
// Channel sum of an RGBA32F accumulated SH volume (body: lookup_sum.glsl).
#extension GL_GOOGLE_include_directive : require
#define LPV_FORMAT rgba32f
#include "lookup_sum.glsl"
