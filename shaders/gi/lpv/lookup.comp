#version 460
// LPV lookup: indirect radiance per G-buffer pixel from the accumulated SH volume, sampled
// trilinearly. Radiance in a cell is intensity / cellSize^2 (docs/lpv.md); the irradiance on a
// surface with normal n is the clamped-cosine integral of the non-negative part of the light
// travelling towards it (direction -n; the 2-band lobes' negative ringing behind emitters would
// cancel real light: docs/lpv.md "Lookup"), and a Lambertian surface sends albedo / pi of it back. The volume is sampled
// half a cell in front of the surface: at the surface itself trilinear filtering mixes in the
// cells behind it, which the geometry volume keeps dark (docs/lpv.md "Lookup" compares both on
// the integrating sphere).
// Light bleeding (Elvek's thesis section 3.3.1, directional-derivative damping, as we read it):
// light that legitimately reaches the front of a surface cannot grow when we step behind it, so
// the irradiance half a cell behind (Eb) and in front (Ef) of the surface are compared, and
// the result is scaled by 1 - strength * max(0, Eb - Ef) / (Eb + Ef).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { LpvLookupPush pc; };
layout(set = 1, binding = LPV_LOOKUP_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = LPV_LOOKUP_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = LPV_LOOKUP_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo;
layout(set = 1, binding = LPV_LOOKUP_BINDING_ACCUMULATION_R) uniform sampler3D accumulationR;
layout(set = 1, binding = LPV_LOOKUP_BINDING_ACCUMULATION_G) uniform sampler3D accumulationG;
layout(set = 1, binding = LPV_LOOKUP_BINDING_ACCUMULATION_B) uniform sampler3D accumulationB;
layout(set = 1, binding = LPV_LOOKUP_BINDING_BUFFER, std430) readonly buffer Injection { uint header[LPV_INJECT_HEADER_INTS]; } injection;
layout(set = 1, binding = LPV_LOOKUP_BINDING_OUTPUT, rgba32f) uniform image2D outIndirect;
layout(set = 1, binding = LPV_LOOKUP_BINDING_SUM) uniform sampler3D accumulationSum; // R + G + B (lookup_sum.glsl)

// Normalised irradiance (R, G, B) at world position p for normal n; zero outside the grid.
vec3 irradiance(vec3 p, vec3 n) {
    vec3 uvw = (p - pc.grid.origin.xyz) / (pc.grid.origin.w * vec3(pc.grid.size.xyz));
    if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0))))
        return vec3(0.0);
    // Irradiance from the light travelling towards the surface (directions around -n), counting
    // only the non-negative part of the 2-band intensity (gi/sh.h, docs/lpv.md "Lookup").
    return shClampedCosineIntegralOfPositivePart(texture(accumulationR, uvw), texture(accumulationG, uvw),
                                                 texture(accumulationB, uvw), -n);
}

// Channel-summed SH at world position p (zero outside the grid).
vec4 shSum(vec3 p) {
    vec3 uvw = (p - pc.grid.origin.xyz) / (pc.grid.origin.w * vec3(pc.grid.size.xyz));
    if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0))))
        return vec4(0.0);
    return texture(accumulationSum, uvw);
}

// Irradiance of the channel-summed light at p and q for normal n (non-negative part, as irradiance()).
vec2 irradianceSum2(vec3 p, vec3 q, vec3 n) {
    return shClampedCosineIntegralOfPositivePart(shSum(p), shSum(q), vec4(0.0), -n).xy;
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, pc.image.xy)))
        return;
    vec4 position = imageLoad(gPosition, px);
    vec3 n = imageLoad(gNormal, px).xyz;
    float nn = dot(n, n);
    vec3 radiance = vec3(0.0);
    if (position.w > 0.0 && nn > 1e-12 && nn < 1e30) {
        n *= inversesqrt(nn);
        float cell = pc.grid.origin.w;
        vec3 x = position.xyz + 0.5 * cell * n;
        vec3 e = irradiance(x, n);
        if (pc.params.x > 0.0) {
            // The damping compares the summed channels: one fetch of the channel-sum volume per
            // point, and both points in one quadrature instead of three channels at each.
            vec2 fb = irradianceSum2(x + 0.5 * cell * n, x - 0.5 * cell * n, n);
            e *= clamp(1.0 - pc.params.x * max(fb.y - fb.x, 0.0) / max(fb.x + fb.y, 1e-30), 0.0, 1.0);
        }
        float m = uintBitsToFloat(injection.header[0]);
        vec3 albedo = clamp(imageLoad(gAlbedo, px).rgb, 0.0, 1.0);
        radiance = albedo * (1.0 / kShPi) * e * (m / (cell * cell));
        if (any(isnan(radiance)) || any(isinf(radiance)))
            radiance = vec3(0.0);
        // Cascades: this level's weight is its own border fade times (1 - fade) of every finer
        // level, so the weights of nested levels sum to 1 wherever the coarsest is not fading.
        float w = pc.params.y > 0.0 ? lpvBorderFade(pc.grid, position.xyz) : 1.0;
        for (int k = 0; k < pc.image.z; ++k)
            w *= 1.0 - lpvBorderFade(pc.finer[k], position.xyz);
        radiance *= w;
    }
    if (pc.params.z > 0.0)
        radiance += imageLoad(outIndirect, px).rgb;
    imageStore(outIndirect, px, vec4(radiance, 1.0));
}
