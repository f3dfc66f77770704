#version 460
#extension GL_GOOGLE_include_directive : require
// Low-resolution optimisation (paper section 3.5), first half: every full-resolution pixel
// interpolates the 1/f-resolution indirect light bilinearly from the 4 nearest gather samples
// unless one lies across a discontinuity (gi/lowres_upsample.h); those pixels are appended to
// the refine list and recomputed at full resolution.
#include "gi/vpl.h"
#include "gi/vpl_refine_list.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_UPSAMPLE_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_UPSAMPLE_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_UPSAMPLE_BINDING_LOW_RES_INDIRECT) uniform sampler2D lowIndirect;
layout(set = 1, binding = VPL_UPSAMPLE_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;
#include "gi/lowres_upsample.h"
VPL_REFINE_LIST_BUFFER(VPL_UPSAMPLE_BINDING_REFINE_LIST, );

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
    ivec2 taps[4];
    vec4 w;
    bool refine = lowResTaps(px, position.xyz, n, depth, int(pc.size.z), ivec2(pc.size.xy), full, pc.params.y, taps, w);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; ++k)
        sum += w[k] * texelFetch(lowIndirect, taps[k], 0).rgb;
    imageStore(outIndirect, px, vec4(sum, 1.0));
    if (refine) {
        VPL_REFINE_LIST_APPEND(px, pc.size.w)
    }
}
