#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow map only: linear depth (see GpuShadowView), no colour targets.
#include "gi/direct_types.h"

layout(push_constant) uniform PushBlock { RasterPush pc; };
// The full raster.vert interface is declared so no vertex output goes unconsumed.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) flat in uint inMaterial;
layout(location = 4) flat in vec4 inBaseColor;
layout(location = 5) flat in vec4 inEmission;
layout(location = 6) flat in vec4 inMaterialParams;

void main() {
    gl_FragDepth = pc.eye.w > 0.0 ? distance(inPosition, pc.eye.xyz) / pc.eye.w : gl_FragCoord.z;
}
