#version 460
#extension GL_GOOGLE_include_directive : require
// Host G-buffer path: world position from the host's depth at the camera's pixel centres, in
// the internal G-buffer's convention (w = 1 on geometry; depth 1 = background = vec4(0)).
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { HostPositionPush pc; };
layout(set = 1, binding = DIRECT_HOST_POSITION_BINDING_DEPTH) uniform sampler2D depth;
layout(set = 1, binding = DIRECT_HOST_POSITION_BINDING_OUTPUT, rgba32f) uniform writeonly image2D outPosition;

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    float d = texelFetch(depth, px, 0).r;
    if (!(d < 1.0)) {
        imageStore(outPosition, px, vec4(0.0));
        return;
    }
    vec2 ndc = (vec2(px) + 0.5) / vec2(pc.size.xy) * 2.0 - 1.0;
    vec4 p = pc.invViewProj * vec4(ndc, d, 1.0);
    imageStore(outPosition, px, vec4(p.xyz / p.w, 1.0));
}
