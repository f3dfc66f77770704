#version 460
#extension GL_GOOGLE_include_directive : require
// Deferred direct lighting over the G-buffer: emission + sum over all punctual lights of
// albedo/pi * E * visibility, with E from the shared KHR_lights_punctual falloff (lights.h)
// and visibility from the shadow atlas (PCF over bilinear depth compares, normal offset and
// slope-scaled bias). The light loop has a run-time trip count so lavapipe's JIT stays small.
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { DeferredPush pc; };

layout(set = 1, binding = 0) uniform sampler2D gPosition;
layout(set = 1, binding = 1) uniform sampler2D gNormal;
layout(set = 1, binding = 2) uniform sampler2D gAlbedo;
layout(set = 1, binding = 3) uniform sampler2D gEmission;
layout(set = 1, binding = 4, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 1, binding = 5, std430) readonly buffer LightShadows { GpuLightShadow lightShadows[]; };
layout(set = 1, binding = 6, std430) readonly buffer ShadowViews { GpuShadowView shadowViews[]; };
layout(set = 1, binding = 7) uniform sampler2DArrayShadow shadowAtlas;
layout(set = 1, binding = 8, rgba32f) uniform writeonly image2D outDirect;

const float kPi = 3.14159265358979;

// Fraction of the PCF kernel that sees the light from `p` (normal `n`, unit `toLight`).
float shadowVisibility(uint lightIndex, vec3 p, vec3 n, vec3 toLight) {
    GpuLightShadow ls = lightShadows[lightIndex];
    if (ls.info.z == GI_SHADOW_NONE)
        return 1.0;
    GpuLight light = lights[lightIndex];
    uint layer = ls.info.x;
    if (ls.info.z == GI_SHADOW_CUBE)
        layer += cubeFace(p - light.positionType.xyz);
    GpuShadowView view = shadowViews[layer];
    bool ortho = view.eye.w <= 0.0;
    // World size of one shadow texel at p, which all biases scale with.
    float texel = ortho ? view.texel.x : view.texel.x * max(dot(p - view.eye.xyz, view.axisArea.xyz), 0.0);
    float cosTheta = clamp(dot(n, toLight), 1e-3, 1.0);
    float tanTheta = min(sqrt(1.0 - cosTheta * cosTheta) / cosTheta, pc.bias.w);
    vec3 q = p + n * (pc.bias.x * texel);
    vec4 clip = view.viewProj * vec4(q, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float depth = ortho ? clip.z : distance(q, view.eye.xyz) / view.eye.w;
    // The PCF footprint reaches (r + 1) texels from the centre (bilinear), so the slope term scales with it.
    depth -= (pc.bias.z + pc.bias.y * float(pc.size.w + 1u) * tanTheta) * texel / view.texel.y;
    float invSize = 1.0 / view.texel.z;
    int r = int(pc.size.w);
    float lit = 0.0;
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
            lit += texture(shadowAtlas, vec4(uv + vec2(x, y) * invSize, float(layer), depth));
    float taps = float((2 * r + 1) * (2 * r + 1));
    return lit / taps;
}

// Irradiance (lux) at p from light i, without shadowing; `toLight` receives the unit direction.
vec3 lightIrradiance(GpuLight light, vec3 p, vec3 n, out vec3 toLight) {
    vec3 radiantI = light.colorIntensity.rgb * light.colorIntensity.w;
    uint type = uint(light.positionType.w);
    if (type == GI_LIGHT_DIRECTIONAL) {
        toLight = -light.directionRange.xyz;
        return radiantI * max(dot(n, toLight), 0.0);
    }
    vec3 d = light.positionType.xyz - p;
    float dist2 = max(dot(d, d), 1e-12);
    float dist = sqrt(dist2);
    toLight = d / dist;
    float atten = lightRangeWindow(dist, light.directionRange.w) / dist2;
    if (type == GI_LIGHT_SPOT)
        atten *= spotConeAttenuation(dot(light.directionRange.xyz, -toLight), light.cone.x, light.cone.y);
    return radiantI * (atten * max(dot(n, toLight), 0.0));
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    vec4 position = texelFetch(gPosition, px, 0);
    if (position.w == 0.0) {
        imageStore(outDirect, px, vec4(0.0, 0.0, 0.0, 1.0));
        return;
    }
    vec3 p = position.xyz;
    vec3 n = texelFetch(gNormal, px, 0).xyz;
    vec3 albedo = texelFetch(gAlbedo, px, 0).rgb;
    vec3 radiance = texelFetch(gEmission, px, 0).rgb;
    for (uint i = 0u; i < pc.size.z; ++i) {
        vec3 toLight;
        vec3 e = lightIrradiance(lights[i], p, n, toLight);
        if (all(equal(e, vec3(0.0))))
            continue;
        radiance += albedo / kPi * e * shadowVisibility(i, p, n, toLight);
    }
    imageStore(outDirect, px, vec4(radiance, 1.0));
}
