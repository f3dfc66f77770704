#version 460
#extension GL_GOOGLE_include_directive : require
// Negative VPLs (paper section 3.3): Halton points (bases 2, 3) pick pixels of the gather
// image; a camera-visible point there passes the VPL light it receives straight on, so it
// becomes a negative VPL at that point whose lobe axis is the weighted mean travel direction
// and whose flux is the VPL irradiance times the surface area the sample stands for:
//     flux = E * pixelArea * (pixels / samples),  pixelArea = pixelSolidAngle * depth^2 / cos(view).
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplGeneratePush pc; };

layout(set = 1, binding = VPL_NEGATIVE_GENERATE_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_NEGATIVE_GENERATE_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_NEGATIVE_GENERATE_BINDING_INCIDENT) uniform sampler2D incident;
layout(set = 1, binding = VPL_NEGATIVE_GENERATE_BINDING_TRAVEL) uniform sampler2D travel;
layout(set = 1, binding = VPL_NEGATIVE_GENERATE_BINDING_NEGATIVE_VPLS, std430) writeonly buffer NegativeVpls {
    VplRecord negativeVpls[];
};

// Grazing views would give a pixel an unbounded world area; |cos| is floored at 0.2 (78 degrees),
// which caps one sample's area at 5x its frontal value.
const float kMinViewCos = 0.2;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint count = pc.info.x;
    if (i >= count)
        return;
    uvec2 size = pc.size.xy;
    int f = int(pc.info.z);
    vec2 u = vec2(vplRadicalInverse(i + 1u, 2u), vplRadicalInverse(i + 1u, 3u));
    ivec2 px = min(ivec2(u * vec2(size)), ivec2(size) - 1);
    ivec2 sample_ = min(px * f + f / 2, ivec2(pc.size.zw) - 1);
    vec4 position = texelFetch(gPosition, sample_, 0);
    vec3 sum = texelFetch(travel, px, 0).xyz;
    VplRecord v;
    v.position = vec4(position.xyz, 0.0);
    v.direction = vec4(0.0, 0.0, 1.0, 0.0);
    v.flux = vec4(0.0);
    float len = length(sum);
    if (position.w > 0.0 && len > 0.0 && !isinf(len)) {
        vec3 n = texelFetch(gNormal, sample_, 0).xyz;
        vec3 toCamera = pc.camera.xyz - position.xyz;
        float depth2 = dot(toCamera, toCamera);
        float cosView = max(abs(dot(n, toCamera * inversesqrt(max(depth2, 1e-30)))), kMinViewCos);
        float omega = vplTexelSolidAngle(float(sample_.x), float(sample_.y), float(pc.size.z), float(pc.size.w),
                                         pc.camera.w) * float(f * f);
        float area = omega * depth2 / cosView * (float(size.x * size.y) / float(count));
        v.position.w = 1.0;
        v.direction = vec4(sum / len, 0.0);
        v.flux = vec4(texelFetch(incident, px, 0).rgb * area, area * (1.0 / GI_VPL_PI));
    }
    negativeVpls[i] = v;
}
