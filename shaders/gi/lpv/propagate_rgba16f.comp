#version 460
// LPV propagation step on RGBA16F SH volumes (body: propagate.glsl).
#extension GL_GOOGLE_include_directive : require
#define LPV_FORMAT rgba16f
#include "propagate.glsl"
