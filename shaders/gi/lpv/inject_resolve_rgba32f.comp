#version 460
// LPV injection resolve into RGBA32F SH volumes (body: inject_resolve.glsl).
#extension GL_GOOGLE_include_directive : require
#define LPV_FORMAT rgba32f
#include "inject_resolve.glsl"
