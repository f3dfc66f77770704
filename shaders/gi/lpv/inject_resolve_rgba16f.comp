#version 460
// LPV injection resolve into RGBA16F SH volumes (body: inject_resolve.glsl).
#extension GL_GOOGLE_include_directive : require
#define LPV_FORMAT rgba16f
#include "inject_resolve.glsl"
