#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow map + reflective shadow map in one pass: linear depth, world position, normal facing
// the light, and the flux each texel reflects (formula in gi/include/gi/frame_data.hpp).
#include "engine/lights.h"
#include "gi/direct_types.h"
#include "surface.h"

layout(push_constant) uniform PushBlock { RasterPush pc; };
// The layer's light, read by rsm.vert.
layout(location = 7) flat in vec4 inLightPositionType;
layout(location = 8) flat in vec4 inLightDirectionRange;
layout(location = 9) flat in vec4 inLightColorIntensity;
layout(location = 10) flat in vec4 inLightCone;

layout(location = 0) out vec4 outPosition; // xyz world position, w = 1 (0 = empty texel)
layout(location = 1) out vec4 outNormal;   // xyz unit normal facing the light
layout(location = 2) out vec4 outFlux;     // rgb reflected flux of this texel (lm-like units: cd sr)

void main() {
    GpuLight light = GpuLight(inLightPositionType, inLightDirectionRange, inLightColorIntensity, inLightCone);
    GpuMaterial m = surfaceMaterial();
    bool ortho = pc.eye.w <= 0.0;
    vec3 toLight = ortho ? -light.directionRange.xyz : light.positionType.xyz - inPosition;
    float dist = length(toLight);
    gl_FragDepth = ortho ? gl_FragCoord.z : dist / pc.eye.w;

    vec3 intensity = light.colorIntensity.rgb * light.colorIntensity.w;
    float footprint = pc.axisArea.w; // ortho: texel area perpendicular to the light
    if (!ortho) {
        vec3 w = -toLight / max(dist, 1e-30);
        footprint = rsmTexelSolidAngle(pc.axisArea.w, max(dot(w, pc.axisArea.xyz), 0.0));
        intensity *= lightRangeWindow(dist, light.directionRange.w);
        if (uint(light.positionType.w) == GI_LIGHT_SPOT)
            intensity *= spotConeAttenuation(dot(w, light.directionRange.xyz), light.cone.x, light.cone.y);
        else if (uint(light.positionType.w) == GI_LIGHT_EMITTER)
            intensity *= max(dot(w, light.directionRange.xyz), 0.0);
    }
    outPosition = vec4(inPosition, 1.0);
    outNormal = vec4(surfaceNormal(ortho ? inPosition + toLight : light.positionType.xyz), 0.0);
    outFlux = vec4(surfaceAlbedo(m) * intensity * footprint, 0.0);
}
