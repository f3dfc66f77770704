#version 460
#extension GL_GOOGLE_include_directive : require
// raster.vert plus the layer's light as flat outputs for rsm.frag: lavapipe loads a storage
// buffer separately for every lane, so the light is read once per vertex, not per fragment.
#include "raster.h"

layout(set = 1, binding = DIRECT_RASTER_BINDING_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };

layout(location = 7) flat out vec4 outLightPositionType;
layout(location = 8) flat out vec4 outLightDirectionRange;
layout(location = 9) flat out vec4 outLightColorIntensity;
layout(location = 10) flat out vec4 outLightCone;

void main() {
    rasterVertex();
    GpuLight light = lights[pc.info.y];
    outLightPositionType = light.positionType;
    outLightDirectionRange = light.directionRange;
    outLightColorIntensity = light.colorIntensity;
    outLightCone = light.cone;
}
