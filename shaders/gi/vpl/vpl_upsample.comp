#version 460
#extension GL_GOOGLE_include_directive : require
// Low-resolution optimisation (paper section 3.5), first half: every full-resolution pixel
// interpolates the 1/f-resolution indirect light bilinearly from the 4 nearest gather samples
// unless one of them lies across a discontinuity (background, normals differing by more than
// the threshold, or a sample off the pixel's tangent plane by more than threshold x depth);
// those pixels are appended to the refine list and recomputed at full resolution.
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplShadePush pc; };

layout(set = 1, binding = 0) uniform sampler2D gPosition;
layout(set = 1, binding = 1) uniform sampler2D gNormal;
layout(set = 1, binding = 2) uniform sampler2D lowIndirect;
layout(set = 1, binding = 3, rgba32f) uniform writeonly image2D outIndirect;
layout(set = 1, binding = 4, std430) buffer RefineList {
    uint refineCount;
    uint refinePad[3];
    uint refinePixels[]; // x | y << 16
};

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 full = ivec2(pc.counts.zw);
    if (any(greaterThanEqual(px, full)))
        return;
    vec4 position = texelFetch(gPosition, px, 0);
    if (position.w == 0.0) {
        imageStore(outIndirect, px, vec4(0.0, 0.0, 0.0, 1.0));
        return;
    }
    vec3 n = texelFetch(gNormal, px, 0).xyz;
    float depth = distance(position.xyz, pc.camera.xyz);
    float threshold = pc.params.y;
    int f = int(pc.size.z);
    ivec2 low = ivec2(pc.size.xy);
    vec2 c = (vec2(px) - float(f / 2)) / float(f);
    ivec2 i0 = ivec2(floor(c));
    vec2 t = c - vec2(i0);
    vec3 sum = vec3(0.0);
    bool refine = false;
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        float w = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
        ivec2 li = clamp(i0 + o, ivec2(0), low - 1);
        if (w <= 0.0)
            continue;
        ivec2 s = min(li * f + f / 2, full - 1);
        vec4 q = texelFetch(gPosition, s, 0);
        vec3 nq = texelFetch(gNormal, s, 0).xyz;
        if (q.w == 0.0 || 1.0 - dot(n, nq) > threshold || abs(dot(q.xyz - position.xyz, n)) > threshold * depth)
            refine = true;
        sum += w * texelFetch(lowIndirect, li, 0).rgb;
    }
    imageStore(outIndirect, px, vec4(sum, 1.0));
    if (refine) {
        uint slot = atomicAdd(refineCount, 1u);
        if (slot < pc.size.w)
            refinePixels[slot] = uint(px.x) | (uint(px.y) << 16);
    }
}
