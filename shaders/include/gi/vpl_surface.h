// GLSL only: a gather pixel's surface (world position and normal) packed in one RGBA32UI texel
// (vpl.surface), written by the interleaved gather so that the filter passes test a neighbour
// with one fetch instead of two. xyz: the position's float bits; w: the normal, 10 bits per
// axis ((n + 1) / 2 in 0..1023), and bit 30 set where there is geometry.
#ifndef VKGI_GI_VPL_SURFACE_H
#define VKGI_GI_VPL_SURFACE_H

const uint kVplSurfaceValid = 1u << 30;

uvec4 vplSurfacePack(vec4 position, vec3 n) {
    if (position.w <= 0.0)
        return uvec4(0u);
    uvec3 q = uvec3(round(clamp(n * 0.5 + 0.5, 0.0, 1.0) * 1023.0));
    return uvec4(floatBitsToUint(position.xyz), q.x | (q.y << 10) | (q.z << 20) | kVplSurfaceValid);
}

bool vplSurfaceValid(uvec4 s) { return (s.w & kVplSurfaceValid) != 0u; }
vec3 vplSurfacePosition(uvec4 s) { return uintBitsToFloat(s.xyz); }
vec3 vplSurfaceNormal(uvec4 s) {
    return vec3(uvec3(s.w, s.w >> 10, s.w >> 20) & 1023u) * (2.0 / 1023.0) - 1.0;
}

#endif
