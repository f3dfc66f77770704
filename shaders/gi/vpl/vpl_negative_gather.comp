#version 460
#extension GL_GOOGLE_include_directive : require
// Subtracts the negative VPLs' light from the gather image (paper section 3.3), clamped at 0:
// indirect radiance cannot be negative, and without visibility the negative term can overshoot.
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_ALBEDO) uniform sampler2D gAlbedo;
layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_NEGATIVE_VPLS, std430) readonly buffer NegativeVpls {
    VplRecord negativeVpls[];
};
layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_POSITIVE_INDIRECT) uniform sampler2D positiveIndirect;
layout(set = 1, binding = VPL_NEGATIVE_GATHER_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;

#define vpls negativeVpls
#include "gi/vpl_gather.h"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    int f = int(pc.size.z);
    ivec2 sample_ = min(px * f + f / 2, ivec2(pc.counts.zw) - 1);
    vec4 position = texelFetch(gPosition, sample_, 0);
    vec3 radiance = texelFetch(positiveIndirect, px, 0).rgb;
    if (position.w > 0.0) {
        vec3 n = texelFetch(gNormal, sample_, 0).xyz;
        vec3 e = vplGatherNegative(position.xyz, n, pc.counts.y, pc.params.x);
        radiance = max(radiance - texelFetch(gAlbedo, sample_, 0).rgb * e * (1.0 / GI_VPL_PI), vec3(0.0));
    }
    imageStore(outIndirect, px, vec4(radiance, 1.0));
}
