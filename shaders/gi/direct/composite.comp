#version 460
#extension GL_GOOGLE_include_directive : require
// Final HDR image = direct + indirect (both linear radiance, nits).
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { CompositePush pc; };
layout(set = 1, binding = 0) uniform sampler2D direct;
layout(set = 1, binding = 1) uniform sampler2D indirect;
layout(set = 1, binding = 2, rgba32f) uniform writeonly image2D outFinal;

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    vec3 c = texelFetch(direct, px, 0).rgb + texelFetch(indirect, px, 0).rgb;
    imageStore(outFinal, px, vec4(c, 1.0));
}
