#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer: world position, camera-facing normal + roughness, albedo + metallic, emission.
#include "gi/direct_types.h"
#include "surface.h"

layout(push_constant) uniform PushBlock { RasterPush pc; };

layout(location = 0) out vec4 outPosition; // xyz world position, w = 1 (0 where nothing was drawn)
layout(location = 1) out vec4 outNormal;   // xyz unit normal facing the camera, w = roughness
layout(location = 2) out vec4 outAlbedo;   // rgb Lambertian albedo, w = metallic
layout(location = 3) out vec4 outEmission; // rgb nits, w = 1

void main() {
    GpuMaterial m = surfaceMaterial();
    outPosition = vec4(inPosition, 1.0);
    outNormal = vec4(surfaceNormal(pc.eye.xyz), m.params.y);
    outAlbedo = vec4(surfaceAlbedo(m), m.params.x);
    // Emission is one-sided (front = counter-clockwise) unless the material is double-sided.
    bool emits = gl_FrontFacing || m.params.w > 0.5;
    outEmission = vec4(emits ? m.emission.rgb : vec3(0.0), 1.0);
}
