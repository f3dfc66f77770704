#version 460
#extension GL_GOOGLE_include_directive : require
// Render-graph test: copies an n x n mip and a 1x1 mip into a buffer: values[y * n + x], then
// the 1x1 value at values[n * n].
#include "engine/test_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push {
    uvec4 size; // x = n
} pc;
layout(set = 1, binding = ENGINE_REDUCE_BINDING_LEVEL, r32ui) uniform readonly uimage2D level;
layout(set = 1, binding = ENGINE_REDUCE_BINDING_TOP, r32ui) uniform readonly uimage2D top;
layout(set = 1, binding = ENGINE_REDUCE_BINDING_VALUES, std430) writeonly buffer Out { uint values[]; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    uint n = pc.size.x;
    if (any(greaterThanEqual(p, uvec2(n))))
        return;
    values[p.y * n + p.x] = imageLoad(level, ivec2(p)).x;
    if (p == uvec2(0))
        values[n * n] = imageLoad(top, ivec2(0)).x;
}
