#version 460
#extension GL_GOOGLE_include_directive : require
// Render-graph test: one mip level of a sum pyramid; each texel is the sum of its 2x2 parent.
#include "engine/test_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push {
    uvec4 size; // x, y = size of the destination mip
} pc;
layout(set = 1, binding = ENGINE_MIP_SUM_BINDING_SOURCE, r32ui) uniform readonly uimage2D src;
layout(set = 1, binding = ENGINE_MIP_SUM_BINDING_TARGET, r32ui) uniform writeonly uimage2D dst;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, pc.size.xy)))
        return;
    ivec2 s = ivec2(2 * p);
    uint sum = imageLoad(src, s).x + imageLoad(src, s + ivec2(1, 0)).x + imageLoad(src, s + ivec2(0, 1)).x +
               imageLoad(src, s + ivec2(1, 1)).x;
    imageStore(dst, ivec2(p), uvec4(sum));
}
